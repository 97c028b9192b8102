//! A small writer of fixed-format IGES text for the reader's tests: entities
//! are added with their parameter data and get their DE pointers back.
#![allow(dead_code)]

/// One entity: type, form, parameter data (`type,...;`), transform DE.
struct Ent {
    kind: i64,
    form: i64,
    params: String,
    transform: usize,
    status: String,
}

/// An IGES file under construction (`,` and `;` delimiters).
pub struct Iges {
    ents: Vec<Ent>,
    /// Global section fields 14 and 15 (unit flag and name), e.g. `2,2HMM`.
    pub units: String,
}

impl Default for Iges {
    fn default() -> Self {
        Iges {
            ents: Vec::new(),
            units: "2,2HMM".into(),
        }
    }
}

impl Iges {
    /// Adds an entity; `params` omits the leading type number and the
    /// final `;`. Returns its DE pointer.
    pub fn add(&mut self, kind: i64, form: i64, params: &str) -> usize {
        self.add_t(kind, form, params, 0)
    }

    /// [`Iges::add`] with a 124 transformation pointer.
    pub fn add_t(&mut self, kind: i64, form: i64, params: &str, transform: usize) -> usize {
        self.ents.push(Ent {
            kind,
            form,
            params: format!("{kind},{params};"),
            transform,
            status: "00000000".into(),
        });
        2 * self.ents.len() - 1
    }

    /// Marks entity `de` physically dependent (status `00010000`).
    pub fn dependent(&mut self, de: usize) {
        if let Some(e) = self.ents.get_mut((de - 1) / 2) {
            e.status = "00010000".into();
        }
    }

    /// Sets the transform pointer of entity `de`.
    pub fn set_transform(&mut self, de: usize, t: usize) {
        if let Some(e) = self.ents.get_mut((de - 1) / 2) {
            e.transform = t;
        }
    }

    /// The file text.
    pub fn text(&self) -> String {
        let (mut d, mut p) = (Vec::new(), Vec::new());
        for (k, e) in self.ents.iter().enumerate() {
            let de = 2 * k + 1;
            let lines = p_lines(&e.params, de, p.len() + 1);
            d.push(format!(
                "{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}",
                e.kind,
                p.len() + 1,
                0,
                0,
                0,
                0,
                e.transform,
                0,
                e.status
            ));
            d.push(format!(
                "{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}",
                e.kind,
                0,
                0,
                lines.len(),
                e.form,
                "",
                "",
                "",
                0
            ));
            p.extend(lines);
        }
        let s = section('S', &["cmm IGES reader test part".to_string()]);
        let g = section(
            'G',
            &[
                "1H,,1H;,4Htest,6Ht.iges,1Hs,1Hp,32,38,6,308,15,4Htest,1.,".to_string(),
                format!(
                    "{},1,0.01,15H20260101.000000,1E-07,100.,1Ha,1Hb,11,0;",
                    self.units
                ),
            ],
        );
        let d = section('D', &d);
        let t = format!(
            "{:<72}T{:>7}",
            format!("S{:>7}G{:>7}D{:>7}P{:>7}", 1, g.len(), d.len(), p.len()),
            1
        );
        [s, g, d, p, vec![t]].concat().join("\n") + "\n"
    }
}

fn section(letter: char, lines: &[String]) -> Vec<String> {
    lines
        .iter()
        .enumerate()
        .map(|(k, l)| format!("{l:<72}{letter}{:>7}", k + 1))
        .collect()
}

/// P records of one entity, broken after delimiters within 64 columns.
fn p_lines(data: &str, de: usize, first_seq: usize) -> Vec<String> {
    let mut chunks: Vec<String> = Vec::new();
    let mut cur = String::new();
    for tok in data.split_inclusive([',', ';']) {
        if cur.len() + tok.len() > 64 && !cur.is_empty() {
            chunks.push(std::mem::take(&mut cur));
        }
        cur.push_str(tok);
    }
    if !cur.is_empty() {
        chunks.push(cur);
    }
    chunks
        .iter()
        .enumerate()
        .map(|(k, c)| format!("{c:<64}{de:>8}P{:>7}", first_seq + k))
        .collect()
}

/// Imports `text` as `t.iges`.
pub fn run(text: &str) -> Result<cmm::cad::Import, cmm::cad::CadError> {
    cmm::cad::iges::import_iges(text, "t.iges", "t", &cmm::cad::ImportOptions::default())
}

/// Points of surface `s` on an `n x n` grid over its whole domain.
pub fn grid_points(s: &cmm::workpiece::format::SurfaceSpec, n: usize) -> Vec<[f64; 3]> {
    let surf = s.to_surface().expect("valid surface");
    let ((u0, u1), (v0, v1)) = surf.domain();
    let mut out = Vec::new();
    for i in 0..=n {
        for j in 0..=n {
            let u = u0 + (u1 - u0) * i as f64 / n as f64;
            let v = v0 + (v1 - v0) * j as f64 / n as f64;
            let p = surf.point(u, v);
            out.push([p.x, p.y, p.z]);
        }
    }
    out
}
