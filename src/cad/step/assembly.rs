//! Product structure: products (PRODUCT_DEFINITION), their shape
//! representations (SHAPE_DEFINITION_REPRESENTATION, untransformed
//! SHAPE_REPRESENTATION_RELATIONSHIPs), placed occurrences
//! (NEXT_ASSEMBLY_USAGE_OCCURRENCE with a CONTEXT_DEPENDENT_SHAPE_REPRESENTATION
//! whose relationship carries an ITEM_DEFINED_TRANSFORMATION) and mapped
//! items (MAPPED_ITEM / REPRESENTATION_MAP), flattened to face instances in
//! the frame of the top product.
use super::access::{as_ref, has_record, Ctx};
use super::parser::{Instance, Value};
use super::placement::{transformation, Transform};
use super::shapes::{rep_items, ItemWalk};
use super::units::rep_length_mm;
use crate::cad::error::CadResult;
use std::collections::{BTreeMap, HashMap, HashSet};

/// Deepest product or mapped-item nesting followed (guards cycles).
pub const MAX_ASSEMBLY_DEPTH: usize = 32;

/// One node of the product tree.
#[derive(Debug, Clone, PartialEq)]
pub struct ProductNode {
    /// Instance label: the product name for the top node, `name#k` for
    /// occurrences (k counts the product's occurrences in the whole tree).
    pub label: String,
    /// PRODUCT_DEFINITION (or representation, for mapped items) entity id.
    pub entity: u64,
    /// Occurrence entity (NEXT_ASSEMBLY_USAGE_OCCURRENCE or MAPPED_ITEM), 0 for the top.
    pub occurrence: u64,
    /// Placement of the node in the top frame.
    pub placement: Transform,
    /// Faces of the node's own shape (children not included).
    pub faces: usize,
    /// Sub-occurrences.
    pub children: Vec<ProductNode>,
}

/// One face to import: which face, where, and under which name prefix.
#[derive(Debug, Clone, PartialEq)]
pub struct FaceInstance {
    /// ADVANCED_FACE / FACE_SURFACE id.
    pub face: u64,
    /// Map from the face's representation into the top frame.
    pub transform: Transform,
    /// Orientation flipped by ORIENTED_FACE / ORIENTED_*_SHELL.
    pub flipped: bool,
    /// Length unit of the face's representation, mm.
    pub length_mm: f64,
    /// Instance path (`sub#1/bracket#2`), empty for faces of the top product.
    pub prefix: String,
}

/// The flattened product structure.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Structure {
    /// Top products.
    pub roots: Vec<ProductNode>,
    /// Faces in tree order.
    pub faces: Vec<FaceInstance>,
}

/// Reads the product structure; empty when the file has none (bare
/// geometry), in which case the caller takes every face once.
pub fn structure(ctx: &Ctx) -> CadResult<Structure> {
    let links = Links::read(ctx)?;
    let mut walk = Walker {
        ctx,
        links: &links,
        counts: HashMap::new(),
        out: Structure::default(),
    };
    for pd in links.roots() {
        let node = walk.product(
            pd,
            0,
            Transform::identity(),
            String::new(),
            0,
            &mut Vec::new(),
        )?;
        walk.out.roots.push(node);
    }
    Ok(walk.out)
}

/// An assembly occurrence: child product and placement in the parent.
#[derive(Debug, Clone)]
struct Occurrence {
    id: u64,
    child: u64,
    relation: Option<u64>,
}

/// Cross references between products, representations and occurrences.
#[derive(Default)]
struct Links {
    /// PRODUCT_DEFINITION ids in file order that have a shape.
    products: Vec<u64>,
    /// Representations of each product.
    reps: BTreeMap<u64, Vec<u64>>,
    /// Owning product of each representation.
    owner: HashMap<u64, u64>,
    /// Untransformed representation relationships (both directions).
    same: HashMap<u64, Vec<u64>>,
    /// Occurrences of each parent product.
    children: BTreeMap<u64, Vec<Occurrence>>,
}

fn params(inst: &Instance, name: &str) -> Option<Vec<Value>> {
    inst.records
        .iter()
        .find(|r| r.name == name)
        .map(|r| r.params.clone())
}

fn ref_at(p: &[Value], i: usize) -> Option<u64> {
    p.get(i).and_then(as_ref)
}

impl Links {
    fn read(ctx: &Ctx) -> CadResult<Links> {
        let mut l = Links::default();
        let pds_of = |pds: u64| {
            ctx.step
                .get(pds)
                .and_then(|i| params(i, "PRODUCT_DEFINITION_SHAPE"))
                .and_then(|p| ref_at(&p, 2))
        };
        let mut nauo_relation: HashMap<u64, u64> = HashMap::new();
        let mut nauos = Vec::new();
        for inst in &ctx.step.instances {
            if let Some(p) = params(inst, "SHAPE_DEFINITION_REPRESENTATION") {
                if let (Some(pd), Some(rep)) = (ref_at(&p, 0).and_then(pds_of), ref_at(&p, 1)) {
                    if !l.reps.contains_key(&pd) {
                        l.products.push(pd);
                    }
                    l.reps.entry(pd).or_default().push(rep);
                    l.owner.entry(rep).or_insert(pd);
                }
            } else if let Some(p) = params(inst, "CONTEXT_DEPENDENT_SHAPE_REPRESENTATION") {
                if let (Some(rel), Some(occ)) = (ref_at(&p, 0), ref_at(&p, 1).and_then(pds_of)) {
                    nauo_relation.insert(occ, rel);
                }
            } else if let Some(p) = params(inst, "NEXT_ASSEMBLY_USAGE_OCCURRENCE") {
                if let (Some(parent), Some(child)) = (ref_at(&p, 3), ref_at(&p, 4)) {
                    nauos.push((inst.id, parent, child));
                }
            } else if let Some(p) = params(inst, "REPRESENTATION_RELATIONSHIP")
                .or_else(|| params(inst, "SHAPE_REPRESENTATION_RELATIONSHIP"))
            {
                let transformed =
                    has_record(inst, "REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION");
                if let (false, Some(a), Some(b)) = (transformed, ref_at(&p, 2), ref_at(&p, 3)) {
                    l.same.entry(a).or_default().push(b);
                    l.same.entry(b).or_default().push(a);
                }
            }
        }
        for (id, parent, child) in nauos {
            let relation = nauo_relation.get(&id).copied();
            l.children.entry(parent).or_default().push(Occurrence {
                id,
                child,
                relation,
            });
        }
        Ok(l)
    }

    /// Products that are nobody's child, in file order.
    fn roots(&self) -> Vec<u64> {
        let children: HashSet<u64> = self.children.values().flatten().map(|o| o.child).collect();
        self.products
            .iter()
            .copied()
            .filter(|pd| !children.contains(pd))
            .collect()
    }

    /// A product's representations with those related to them without a
    /// transformation (and not owned by another product).
    fn shape_reps(&self, pd: u64) -> Vec<u64> {
        let mut out: Vec<u64> = Vec::new();
        let mut stack: Vec<u64> = self.reps.get(&pd).cloned().unwrap_or_default();
        while let Some(r) = stack.pop() {
            if out.contains(&r) || self.owner.get(&r).is_some_and(|o| *o != pd) {
                continue;
            }
            out.push(r);
            stack.extend(self.same.get(&r).into_iter().flatten().copied());
        }
        out.sort_unstable();
        out
    }
}

struct Walker<'a, 'b> {
    ctx: &'a Ctx<'b>,
    links: &'a Links,
    counts: HashMap<String, usize>,
    out: Structure,
}

impl Walker<'_, '_> {
    fn label(&mut self, base: &str) -> String {
        let k = self.counts.entry(base.to_string()).or_insert(0);
        *k += 1;
        format!("{base}#{k}")
    }

    /// Walks product `pd` placed by `at`; returns its tree node.
    fn product(
        &mut self,
        pd: u64,
        occurrence: u64,
        at: Transform,
        prefix: String,
        depth: usize,
        path: &mut Vec<u64>,
    ) -> CadResult<ProductNode> {
        let name = product_name(self.ctx, pd);
        let mut node = ProductNode {
            label: if occurrence == 0 {
                name
            } else {
                last_label(&prefix)
            },
            entity: pd,
            occurrence,
            placement: at,
            faces: 0,
            children: Vec::new(),
        };
        if depth > MAX_ASSEMBLY_DEPTH || path.contains(&pd) {
            return Ok(node);
        }
        path.push(pd);
        let reps = self.links.shape_reps(pd);
        let unit = reps
            .iter()
            .find_map(|r| rep_length_mm(self.ctx, *r))
            .unwrap_or(self.ctx.length_mm);
        for rep in reps.iter().copied() {
            self.rep(rep, at, &prefix, depth, &mut node)?;
        }
        let occurrences = self.links.children.get(&pd).cloned().unwrap_or_default();
        for occ in occurrences {
            let child_reps = self.links.shape_reps(occ.child);
            let child_unit = child_reps
                .iter()
                .find_map(|r| rep_length_mm(self.ctx, *r))
                .unwrap_or(self.ctx.length_mm);
            let local = match occ.relation {
                Some(rel) => relation_transform(self.ctx, rel, child_unit, unit)?,
                None => Transform::identity(),
            };
            let base = product_name(self.ctx, occ.child);
            let label = self.label(&base);
            let child_prefix = join(&prefix, &label);
            let child = self.product(
                occ.child,
                occ.id,
                at.after(&local),
                child_prefix,
                depth + 1,
                path,
            )?;
            node.children.push(child);
        }
        path.pop();
        Ok(node)
    }

    /// Adds the faces of representation `rep` (and of its mapped items).
    fn rep(
        &mut self,
        rep: u64,
        at: Transform,
        prefix: &str,
        depth: usize,
        node: &mut ProductNode,
    ) -> CadResult<()> {
        let length_mm = rep_length_mm(self.ctx, rep).unwrap_or(self.ctx.length_mm);
        let ItemWalk { faces, mapped } = rep_items(self.ctx, rep)?;
        let mut faces = faces;
        faces.sort_by_key(|(f, _)| self.ctx.step.position(*f));
        for (face, flipped) in faces {
            self.out.faces.push(FaceInstance {
                face,
                transform: at,
                flipped,
                length_mm,
                prefix: prefix.to_string(),
            });
            node.faces += 1;
        }
        for m in mapped {
            self.mapped(m, at, prefix, depth, node, length_mm)?;
        }
        Ok(())
    }

    /// A MAPPED_ITEM: the mapped representation placed by
    /// `target * origin^-1`, as a child node.
    fn mapped(
        &mut self,
        item: u64,
        at: Transform,
        prefix: &str,
        depth: usize,
        node: &mut ProductNode,
        unit: f64,
    ) -> CadResult<()> {
        if depth > MAX_ASSEMBLY_DEPTH {
            return Ok(());
        }
        let args = self.ctx.args(item, "MAPPED_ITEM")?;
        let map = self.ctx.args(args.reference(1)?, "REPRESENTATION_MAP")?;
        let (origin, rep) = (map.reference(0)?, map.reference(1)?);
        let rep_unit = rep_length_mm(self.ctx, rep).unwrap_or(unit);
        let to = transformation(self.ctx, args.reference(2)?, unit, unit)?;
        let from = transformation(self.ctx, origin, rep_unit, rep_unit)?;
        let local = to.after(&inverse(&from));
        let base = match self.links.owner.get(&rep) {
            Some(pd) => product_name(self.ctx, *pd),
            None => non_empty(args.string(0)?, "item"),
        };
        let label = self.label(&base);
        let child_prefix = join(prefix, &label);
        let place = at.after(&local);
        let mut child = ProductNode {
            label,
            entity: rep,
            occurrence: item,
            placement: place,
            faces: 0,
            children: Vec::new(),
        };
        self.rep(rep, place, &child_prefix, depth + 1, &mut child)?;
        node.children.push(child);
        Ok(())
    }
}

fn inverse(t: &Transform) -> Transform {
    let inv = t
        .linear
        .try_inverse()
        .unwrap_or_else(crate::math::Mat3::identity);
    Transform {
        linear: inv,
        shift: -(inv * t.shift),
    }
}

/// The child-to-parent map of a (transformed) representation relationship.
fn relation_transform(ctx: &Ctx, rel: u64, child_mm: f64, parent_mm: f64) -> CadResult<Transform> {
    let inst = ctx.inst(rel)?;
    let Some(p) = params(inst, "REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION") else {
        return Ok(Transform::identity());
    };
    match ref_at(&p, 0) {
        Some(op) => transformation(ctx, op, child_mm, parent_mm),
        None => Err(ctx.err(inst, "transformation operator is not a reference")),
    }
}

fn join(prefix: &str, label: &str) -> String {
    if prefix.is_empty() {
        label.to_string()
    } else {
        format!("{prefix}/{label}")
    }
}

fn last_label(prefix: &str) -> String {
    prefix.rsplit('/').next().unwrap_or(prefix).to_string()
}

fn non_empty(s: &str, fallback: &str) -> String {
    let t = s.trim();
    if t.is_empty() {
        fallback.to_string()
    } else {
        t.replace('/', "_")
    }
}

/// The PRODUCT name (else its id) of a PRODUCT_DEFINITION, `#id` when absent.
pub fn product_name(ctx: &Ctx, pd: u64) -> String {
    let fallback = format!("product{pd}");
    let product = ctx
        .args(pd, "PRODUCT_DEFINITION")
        .and_then(|a| a.reference(2))
        .and_then(|f| ctx.first(f))
        .and_then(|a| a.reference(2))
        .and_then(|p| ctx.args(p, "PRODUCT"));
    let Ok(product) = product else {
        return fallback;
    };
    let name = product.string(1).unwrap_or("");
    let id = product.string(0).unwrap_or("");
    non_empty(if name.trim().is_empty() { id } else { name }, &fallback)
}
