//! STEP assemblies: product instances placed into the top frame, checked
//! against the single part moved by hand-written rigid maps (the placements
//! the assembly was written with), and a synthetic nested assembly with a
//! mapped item whose face corners are checked against composed frames.
mod cad_common;
use cad_common::eval;
use cmm::cad::{import, step::import_step, ImportOptions};

fn path(name: &str) -> Option<String> {
    // CMM_CAD_DIR overrides the directory (a checkout whose parent has no shared/).
    let dir = std::env::var("CMM_CAD_DIR")
        .unwrap_or_else(|_| format!("{}/../shared/cad", env!("CARGO_MANIFEST_DIR")));
    let p = format!("{dir}/{name}");
    if std::path::Path::new(&p).exists() {
        return Some(p);
    }
    println!("note: {p} not found; skipping");
    None
}

type V = [f64; 3];

/// Rotation by `deg` about z, then translation by `t`.
fn rz_then(deg: f64, t: V, p: V) -> V {
    let (s, c) = deg.to_radians().sin_cos();
    [
        c * p[0] - s * p[1] + t[0],
        s * p[0] + c * p[1] + t[1],
        p[2] + t[2],
    ]
}

fn dist(a: V, b: V) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

fn domain(s: &cmm::workpiece::format::SurfaceSpec) -> ((f64, f64), (f64, f64)) {
    let (p, q) = (s.degree[0], s.degree[1]);
    (
        (s.knots_u[p], s.knots_u[s.knots_u.len() - p - 1]),
        (s.knots_v[q], s.knots_v[s.knots_v.len() - q - 1]),
    )
}

/// 3-D points of a face's trim loops, one polyline per loop.
fn trim_3d(s: &cmm::workpiece::format::SurfaceSpec) -> Vec<Vec<V>> {
    let t = s.trim.as_ref().expect("trimmed");
    std::iter::once(&t.outer)
        .chain(&t.holes)
        .map(|l| l.iter().map(|uv| eval(s, uv[0], uv[1])).collect())
        .collect()
}

fn seg_dist(q: V, a: V, b: V) -> f64 {
    let ab = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let aq = [q[0] - a[0], q[1] - a[1], q[2] - a[2]];
    let len2 = ab.iter().map(|x| x * x).sum::<f64>();
    let s = if len2 > 0.0 {
        (ab.iter().zip(aq).map(|(x, y)| x * y).sum::<f64>() / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    dist(q, [a[0] + s * ab[0], a[1] + s * ab[1], a[2] + s * ab[2]])
}

/// Largest distance from a point of loops `a` to the closed polylines `b`.
fn loops_gap(a: &[Vec<V>], b: &[Vec<V>]) -> f64 {
    let to_b = |q: V| {
        b.iter()
            .flat_map(|l| (0..l.len()).map(move |k| seg_dist(q, l[k], l[(k + 1) % l.len()])))
            .fold(f64::INFINITY, f64::min)
    };
    a.iter().flatten().map(|q| to_b(*q)).fold(0.0, f64::max)
}

#[test]
fn fixture_assembly_is_three_placed_brackets() {
    let (Some(asm), Some(part)) = (path("fixture-assembly.step"), path("io1-cm-214.stp")) else {
        return;
    };
    let asm = import(&asm).expect("assembly imports");
    let part = import(&part).expect("part imports");
    assert_eq!(part.faces.len(), 29);
    assert_eq!(asm.faces.len(), 87, "three instances of 29 faces");
    assert!(asm.diagnostics.is_empty(), "{:?}", asm.diagnostics);
    let instance = |k: usize| -> Vec<&cmm::workpiece::format::SurfaceSpec> {
        let prefix = format!("bracket#{k}/");
        let faces: Vec<_> = asm
            .workpiece
            .surfaces
            .iter()
            .filter(|s| s.name.starts_with(&prefix))
            .collect();
        assert_eq!(faces.len(), 29, "instance {k}");
        faces
    };
    // Instance 1 is the part where it was modelled: its face boundaries
    // coincide with the single part's (both sampled to the chord tolerance).
    let first = instance(1);
    let mut gap: f64 = 0.0;
    for (single, placed) in part.workpiece.surfaces.iter().zip(&first) {
        let (a, b) = (trim_3d(placed), trim_3d(single));
        gap = gap.max(loops_gap(&a, &b)).max(loops_gap(&b, &a));
        assert_eq!(single.reversed, placed.reversed, "{}", placed.name);
    }
    assert!(
        gap < 2e-3,
        "instance 1 boundaries off the part's by {gap:e} mm"
    );
    // The placements the assembly was written with (rotation about z, shift).
    let placements = [(90.0, [150.0, 0.0, 10.0]), (180.0, [0.0, 120.0, 20.0])];
    let mut worst: f64 = 0.0;
    for (k, (deg, t)) in placements.iter().enumerate() {
        for (base, placed) in first.iter().zip(instance(k + 2)) {
            assert_eq!(base.trim, placed.trim, "{}: same trim", placed.name);
            assert_eq!(base.reversed, placed.reversed, "{}", placed.name);
            let ((u0, u1), (v0, v1)) = domain(placed);
            assert_eq!(domain(base), ((u0, u1), (v0, v1)));
            for a in 0..=8 {
                for b in 0..=8 {
                    let u = u0 + (u1 - u0) * a as f64 / 8.0;
                    let v = v0 + (v1 - v0) * b as f64 / 8.0;
                    let want = rz_then(*deg, *t, eval(base, u, v));
                    worst = worst.max(dist(want, eval(placed, u, v)));
                }
            }
        }
    }
    assert!(worst < 1e-9, "placed faces off by {worst:e} mm");
}

const PART_FACE: &str = "\
#10=CARTESIAN_POINT('',(0.,0.,0.));#11=DIRECTION('',(0.,0.,1.));#12=DIRECTION('',(1.,0.,0.));\n\
#13=AXIS2_PLACEMENT_3D('',#10,#11,#12);#14=PLANE('',#13);\n\
#20=CARTESIAN_POINT('',(0.,0.,0.));#21=CARTESIAN_POINT('',(10.,0.,0.));\n\
#22=CARTESIAN_POINT('',(10.,10.,0.));#23=CARTESIAN_POINT('',(0.,10.,0.));\n\
#24=VERTEX_POINT('',#20);#25=VERTEX_POINT('',#21);#26=VERTEX_POINT('',#22);#27=VERTEX_POINT('',#23);\n\
#30=DIRECTION('',(1.,0.,0.));#31=VECTOR('',#30,1.);#32=LINE('',#20,#31);\n\
#33=DIRECTION('',(0.,1.,0.));#34=VECTOR('',#33,1.);#35=LINE('',#21,#34);\n\
#36=DIRECTION('',(-1.,0.,0.));#37=VECTOR('',#36,1.);#38=LINE('',#22,#37);\n\
#39=DIRECTION('',(0.,-1.,0.));#40=VECTOR('',#39,1.);#41=LINE('',#23,#40);\n\
#42=EDGE_CURVE('',#24,#25,#32,.T.);#43=EDGE_CURVE('',#25,#26,#35,.T.);\n\
#44=EDGE_CURVE('',#26,#27,#38,.T.);#45=EDGE_CURVE('',#27,#24,#41,.T.);\n\
#46=ORIENTED_EDGE('',*,*,#42,.T.);#47=ORIENTED_EDGE('',*,*,#43,.T.);\n\
#48=ORIENTED_EDGE('',*,*,#44,.T.);#49=ORIENTED_EDGE('',*,*,#45,.T.);\n\
#50=EDGE_LOOP('',(#46,#47,#48,#49));#51=FACE_OUTER_BOUND('',#50,.T.);\n\
#52=ADVANCED_FACE('',(#51),#14,.T.);\n";

/// `#id=AXIS2_PLACEMENT_3D` at `o` with axis `z` and reference `x` (ids id..id+3).
fn axis(id: u32, o: V, z: V, x: V) -> String {
    format!(
        "#{a}=CARTESIAN_POINT('',({:?},{:?},{:?}));#{b}=DIRECTION('',({:?},{:?},{:?}));\
#{c}=DIRECTION('',({:?},{:?},{:?}));#{id}=AXIS2_PLACEMENT_3D('',#{a},#{b},#{c});\n",
        o[0],
        o[1],
        o[2],
        z[0],
        z[1],
        z[2],
        x[0],
        x[1],
        x[2],
        a = id + 1,
        b = id + 2,
        c = id + 3
    )
}

/// A product `name` (PRODUCT_DEFINITION `pd`) with shape representation `rep`.
fn product(pd: u32, name: &str, rep: u32, items: &str) -> String {
    format!(
        "#{p}=PRODUCT('{name}','{name}','',());#{f}=PRODUCT_DEFINITION_FORMATION('','',#{p});\n\
#{pd}=PRODUCT_DEFINITION('design','',#{f},$);#{s}=PRODUCT_DEFINITION_SHAPE('','',#{pd});\n\
#{rep}=SHAPE_REPRESENTATION('',({items}),#901);#{d}=SHAPE_DEFINITION_REPRESENTATION(#{s},#{rep});\n",
        p = pd + 1,
        f = pd + 2,
        s = pd + 3,
        d = pd + 4
    )
}

/// NAUO `id` of child `child` in `parent`, placed by item `from` -> `to`.
fn occurrence(id: u32, parent: u32, child: u32, reps: (u32, u32), from: u32, to: u32) -> String {
    format!(
        "#{id}=NEXT_ASSEMBLY_USAGE_OCCURRENCE('{id}','','',#{parent},#{child},$);\n\
#{t}=ITEM_DEFINED_TRANSFORMATION('','',#{from},#{to});\n\
#{r}=(REPRESENTATION_RELATIONSHIP('','',#{c},#{p})REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION(#{t})SHAPE_REPRESENTATION_RELATIONSHIP());\n\
#{s}=PRODUCT_DEFINITION_SHAPE('','',#{id});#{q}=CONTEXT_DEPENDENT_SHAPE_REPRESENTATION(#{r},#{s});\n",
        t = id + 1,
        r = id + 2,
        s = id + 3,
        q = id + 4,
        c = reps.0,
        p = reps.1
    )
}

/// `o + p.x x + p.y (z x x) + p.z z`: a frame's local point in world coordinates.
fn frame_point(o: V, z: V, x: V, p: V) -> V {
    let y = [
        z[1] * x[2] - z[2] * x[1],
        z[2] * x[0] - z[0] * x[2],
        z[0] * x[1] - z[1] * x[0],
    ];
    [0, 1, 2].map(|i| o[i] + p[0] * x[i] + p[1] * y[i] + p[2] * z[i])
}

#[test]
fn nested_assembly_and_mapped_item_compose_placements() {
    let (zz, xx) = ([0.0, 0.0, 1.0], [1.0, 0.0, 0.0]);
    // Part P (faces), sub-assembly S (two P), top T (one S and P mapped).
    let s1 = ([100.0, 0.0, 0.0], zz, [0.0, 1.0, 0.0]);
    let s2 = ([0.0, 50.0, 0.0], zz, [-1.0, 0.0, 0.0]);
    let t1 = ([0.0, 0.0, 30.0], [0.0, -1.0, 0.0], xx);
    let t2 = ([-20.0, -20.0, -20.0], zz, xx);
    let mut data = String::from(PART_FACE);
    data += "#60=OPEN_SHELL('',(#52));#61=SHELL_BASED_SURFACE_MODEL('',(#60));\n";
    data += &axis(100, [0.0; 3], zz, xx);
    data += &axis(110, s1.0, s1.1, s1.2);
    data += &axis(120, s2.0, s2.1, s2.2);
    data += &axis(130, t1.0, t1.1, t1.2);
    data += &axis(140, t2.0, t2.1, t2.2);
    data += &product(200, "P", 205, "#100,#61");
    data += &product(210, "S", 215, "#100,#110,#120");
    data += "#150=REPRESENTATION_MAP(#100,#205);#151=MAPPED_ITEM('m',#150,#140);\n";
    data += &product(220, "T", 225, "#100,#130,#151");
    data += &occurrence(300, 210, 200, (205, 215), 100, 110);
    data += &occurrence(310, 210, 200, (205, 215), 100, 120);
    data += &occurrence(320, 220, 210, (215, 225), 100, 130);
    let text = cad_common::wrap(&data);
    let imp = import_step(&text, "t.step", "t", &ImportOptions::default()).expect("imports");
    let names: Vec<&str> = imp.faces.iter().map(|f| f.name.as_str()).collect();
    assert_eq!(names, ["P#1/face1", "S#1/P#2/face1", "S#1/P#3/face1"]);
    let corners: [V; 4] = [
        [0.0, 0.0, 0.0],
        [10.0, 0.0, 0.0],
        [10.0, 10.0, 0.0],
        [0.0, 10.0, 0.0],
    ];
    let at = |f: (V, V, V)| move |p: V| frame_point(f.0, f.1, f.2, p);
    let expected: [Vec<V>; 3] = [
        corners.iter().map(|&c| at(t2)(c)).collect(),
        corners.iter().map(|&c| at(t1)(at(s1)(c))).collect(),
        corners.iter().map(|&c| at(t1)(at(s2)(c))).collect(),
    ];
    for (spec, want) in imp.workpiece.surfaces.iter().zip(&expected) {
        let trim = spec.trim.as_ref().expect("trimmed");
        let got: Vec<V> = trim
            .outer
            .iter()
            .map(|uv| eval(spec, uv[0], uv[1]))
            .collect();
        assert_eq!(got.len(), 4, "{}", spec.name);
        for w in want {
            let best = got
                .iter()
                .map(|g| dist(*g, *w))
                .fold(f64::INFINITY, f64::min);
            assert!(best < 1e-9, "{}: corner {w:?} off by {best:e}", spec.name);
        }
    }
    assert_eq!(imp.products.len(), 1);
    let top = &imp.products[0];
    assert_eq!(top.label, "T");
    let labels: Vec<&str> = top.children.iter().map(|c| c.label.as_str()).collect();
    assert_eq!(labels, ["P#1", "S#1"]);
    assert_eq!(top.children[1].children.len(), 2);
}
