//! B-spline forms without explicit knots, rational complex instances,
//! offset and rectangular-trimmed surfaces, oriented faces and absurd
//! coordinates, on small synthetic STEP texts checked against analytic
//! shapes.
//!
//! The knot vectors derived for UNIFORM / QUASI_UNIFORM / BEZIER /
//! PIECEWISE_BEZIER forms are checked through linear precision: control
//! points at the Greville abscissae of the expected knot vector reproduce
//! `S(u, v) = (u, v, 0)` exactly, which fails for any other knot vector.
mod cad_common;
use cad_common::{eval, wrap};
use cmm::cad::step::access::Ctx;
use cmm::cad::step::bspline::{bspline_curve, bspline_surface};
use cmm::cad::step::curves::Space;
use cmm::cad::{step::import_step, ImportOptions};

/// Greville abscissae of a knot vector for degree `p`.
fn greville(knots: &[f64], p: usize) -> Vec<f64> {
    let n = knots.len() - p - 1;
    (0..n)
        .map(|i| knots[i + 1..=i + p].iter().sum::<f64>() / p as f64)
        .collect()
}

/// CARTESIAN_POINTs `#id..` for the grid `xs x ys` (z = 0); returns the
/// data and the STEP grid text `((#a,#b),(...))`.
fn grid(first: u32, xs: &[f64], ys: &[f64]) -> (String, String) {
    let mut data = String::new();
    let mut rows = Vec::new();
    let mut id = first;
    for x in xs {
        let mut row = Vec::new();
        for y in ys {
            data += &format!("#{id}=CARTESIAN_POINT('',({x:?},{y:?},0.));\n");
            row.push(format!("#{id}"));
            id += 1;
        }
        rows.push(format!("({})", row.join(",")));
    }
    (data, format!("({})", rows.join(",")))
}

fn with_ctx<T>(data: &str, f: impl Fn(&Ctx) -> T) -> T {
    let text = wrap(data);
    let step = cmm::cad::parse_step_str(&text).expect("parses");
    let ctx = Ctx {
        step: &step,
        file: "t.step",
        length_mm: 1.0,
        angle_rad: 1.0,
    };
    f(&ctx)
}

/// (record, degree, control points, expected knots, domain)
fn forms() -> Vec<(&'static str, usize, usize, Vec<f64>)> {
    vec![
        (
            "QUASI_UNIFORM_SURFACE",
            2,
            4,
            vec![0., 0., 0., 1., 2., 2., 2.],
        ),
        ("UNIFORM_SURFACE", 2, 4, vec![-2., -1., 0., 1., 2., 3., 4.]),
        ("BEZIER_SURFACE", 3, 4, vec![0., 0., 0., 0., 1., 1., 1., 1.]),
        (
            "PIECEWISE_BEZIER_SURFACE",
            2,
            5,
            vec![0., 0., 0., 1., 1., 2., 2., 2.],
        ),
    ]
}

#[test]
fn derived_knot_vectors_have_linear_precision() {
    for (record, p, n, knots) in forms() {
        let g = greville(&knots, p);
        assert_eq!(g.len(), n);
        let (pts, text) = grid(10, &g, &g);
        let data = format!("{pts}#1={record}('',{p},{p},{text},.UNSPECIFIED.,.F.,.F.,.F.);\n");
        let spec = with_ctx(&data, |ctx| bspline_surface(ctx, 1)).expect(record);
        assert_eq!(spec.knots_u, knots, "{record}");
        assert_eq!(spec.knots_v, knots, "{record}");
        let (lo, hi) = (knots[p], knots[knots.len() - p - 1]);
        for a in 0..=10 {
            for b in 0..=10 {
                let u = lo + (hi - lo) * a as f64 / 10.0;
                let v = lo + (hi - lo) * b as f64 / 10.0;
                let s = eval(&spec, u, v);
                let err = (s[0] - u).abs() + (s[1] - v).abs() + s[2].abs();
                assert!(err < 1e-12, "{record}: S({u},{v}) = {s:?}");
            }
        }
        // The same form as a curve (record name with CURVE).
        let curve = record.replace("SURFACE", "CURVE");
        let row: Vec<String> = (0..n).map(|i| format!("#{}", 10 + i * n)).collect();
        let data = format!(
            "{pts}#1={curve}('',{p},({}),.UNSPECIFIED.,.F.,.F.);\n",
            row.join(",")
        );
        let c = with_ctx(&data, |ctx| bspline_curve(ctx, 1, Space::Model)).expect(&curve);
        for a in 0..=10 {
            let u = lo + (hi - lo) * a as f64 / 10.0;
            let q = c.point(u);
            let y0 = g[0];
            assert!(
                (q.x - u).abs() < 1e-12 && (q.y - y0).abs() < 1e-12,
                "{curve}: {u} -> {q}"
            );
        }
    }
}

#[test]
fn wrong_counts_for_a_form_are_errors() {
    let (pts, text) = grid(10, &[0.0, 1.0, 2.0, 3.0], &[0.0, 1.0]);
    let data = format!("{pts}#1=BEZIER_SURFACE('',2,1,{text},.UNSPECIFIED.,.F.,.F.,.F.);\n");
    let err = with_ctx(&data, |ctx| bspline_surface(ctx, 1)).expect_err("4 points, degree 2");
    assert!(err.to_string().contains("Bezier"), "{err}");
}

/// Weighted quarter circle of radius `r` (u) swept along z from 0 to `h`
/// (v), as a complex rational QUASI_UNIFORM instance.
fn quarter_cylinder(r: f64, h: f64) -> String {
    let mut data = String::new();
    let pts = [[r, 0.0], [r, r], [0.0, r]];
    for (i, p) in pts.iter().enumerate() {
        for (j, z) in [0.0, h].iter().enumerate() {
            data += &format!(
                "#{}=CARTESIAN_POINT('',({:?},{:?},{z:?}));\n",
                10 + 2 * i + j,
                p[0],
                p[1]
            );
        }
    }
    let w = std::f64::consts::FRAC_1_SQRT_2;
    data += &format!(
        "#1=(BOUNDED_SURFACE()B_SPLINE_SURFACE(2,1,((#10,#11),(#12,#13),(#14,#15)),.UNSPECIFIED.,.F.,.F.,.F.)\
GEOMETRIC_REPRESENTATION_ITEM()QUASI_UNIFORM_SURFACE()RATIONAL_B_SPLINE_SURFACE(((1.,1.),({w:?},{w:?}),(1.,1.)))\
REPRESENTATION_ITEM('')SURFACE());\n"
    );
    data
}

#[test]
fn complex_rational_quasi_uniform_surface_is_a_cylinder_patch() {
    let (r, h) = (7.0, 3.0);
    let spec = with_ctx(&quarter_cylinder(r, h), |ctx| bspline_surface(ctx, 1)).expect("reads");
    assert!(spec.weights.is_some());
    for a in 0..=20 {
        for b in 0..=4 {
            let s = eval(&spec, a as f64 / 20.0, b as f64 / 4.0);
            assert!(
                (s[0].hypot(s[1]) - r).abs() < 1e-12,
                "{s:?} on the cylinder"
            );
            let t = 1e-12;
            assert!(
                s[0] >= -t && s[1] >= -t && s[2] >= -t && s[2] <= h + t,
                "{s:?}"
            );
        }
    }
    // And as a complex rational curve (the quarter circle itself).
    let w = std::f64::consts::FRAC_1_SQRT_2;
    let data = format!(
        "#10=CARTESIAN_POINT('',({r:?},0.));#11=CARTESIAN_POINT('',({r:?},{r:?}));#12=CARTESIAN_POINT('',(0.,{r:?}));\n\
#1=(BOUNDED_CURVE()B_SPLINE_CURVE(2,(#10,#11,#12),.CIRCULAR_ARC.,.F.,.F.)CURVE()GEOMETRIC_REPRESENTATION_ITEM()\
BEZIER_CURVE()RATIONAL_B_SPLINE_CURVE((1.,{w:?},1.))REPRESENTATION_ITEM(''));\n"
    );
    let c = with_ctx(&data, |ctx| bspline_curve(ctx, 1, Space::Model)).expect("curve");
    for a in 0..=20 {
        let q = c.point(a as f64 / 20.0);
        assert!((q.x.hypot(q.y) - r).abs() < 1e-12, "{q}");
    }
}

const AXIS: &str = "#1=CARTESIAN_POINT('',(0.,0.,0.));#2=DIRECTION('',(0.,0.,1.));#3=DIRECTION('',(1.,0.,0.));#4=AXIS2_PLACEMENT_3D('',#1,#2,#3);\n";

/// A full circle of radius `r` at height `z` as a one-edge loop (ids from `b`).
fn circle_loop(b: u32, z: f64, r: f64, bound: &str, forward: &str) -> String {
    format!(
        "#{b}=CARTESIAN_POINT('',(0.,0.,{z:?}));#{b1}=AXIS2_PLACEMENT_3D('',#{b},#2,#3);#{b2}=CIRCLE('',#{b1},{r:?});\n\
#{b3}=CARTESIAN_POINT('',({r:?},0.,{z:?}));#{b4}=VERTEX_POINT('',#{b3});#{b5}=EDGE_CURVE('',#{b4},#{b4},#{b2},.T.);\n\
#{b6}=ORIENTED_EDGE('',*,*,#{b5},{forward});#{b7}=EDGE_LOOP('',(#{b6}));#{b8}={bound}('',#{b7},.T.);\n",
        b1 = b + 1,
        b2 = b + 2,
        b3 = b + 3,
        b4 = b + 4,
        b5 = b + 5,
        b6 = b + 6,
        b7 = b + 7,
        b8 = b + 8
    )
}

fn import(data: &str) -> cmm::cad::Import {
    import_step(&wrap(data), "t.step", "t", &ImportOptions::default()).expect("imports")
}

#[test]
fn offset_cylinder_face_lies_on_the_grown_radius() {
    let (r, d) = (10.0, 2.5);
    let data = format!(
        "{AXIS}#5=CYLINDRICAL_SURFACE('',#4,{r:?});#6=OFFSET_SURFACE('',#5,{d:?},.F.);\n{}{}\
#50=ADVANCED_FACE('band',(#28,#48),#6,.T.);\n",
        circle_loop(20, 0.0, r + d, "FACE_OUTER_BOUND", ".T."),
        circle_loop(40, 4.0, r + d, "FACE_BOUND", ".F.")
    );
    let imp = import(&data);
    assert_eq!(imp.faces.len(), 1);
    assert!(imp.diagnostics.is_empty(), "{:?}", imp.diagnostics);
    assert_eq!(imp.faces[0].surface_type, "OFFSET_SURFACE");
    let s = &imp.workpiece.surfaces[0];
    let trim = s.trim.as_ref().expect("trim");
    for uv in &trim.outer {
        let p = eval(s, uv[0], uv[1]);
        assert!((p[0].hypot(p[1]) - (r + d)).abs() < 1e-9, "{p:?}");
    }
    for k in 0..=10 {
        let p = eval(
            s,
            s.knots_u[0] + (s.knots_u[s.knots_u.len() - 1] - s.knots_u[0]) * k as f64 / 10.0,
            s.knots_v[1],
        );
        assert!((p[0].hypot(p[1]) - (r + d)).abs() < 1e-9, "{p:?}");
    }
}

/// A 10 x 10 square face at height `z` on surface `#surf` (ids 20..).
fn square_face(z: f64, surf: u32, face: u32) -> String {
    let c = [[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]];
    let mut data = String::new();
    for (k, p) in c.iter().enumerate() {
        let id = 20 + k as u32;
        data += &format!(
            "#{id}=CARTESIAN_POINT('',({:?},{:?},{z:?}));#{}=VERTEX_POINT('',#{id});\n",
            p[0],
            p[1],
            id + 10
        );
    }
    for k in 0..4u32 {
        let (a, b) = (k, (k + 1) % 4);
        let d = [
            c[b as usize][0] - c[a as usize][0],
            c[b as usize][1] - c[a as usize][1],
        ];
        data += &format!(
            "#{}=DIRECTION('',({:?},{:?},0.));#{}=VECTOR('',#{},10.);#{}=LINE('',#{},#{});\
#{}=EDGE_CURVE('',#{},#{},#{},.T.);#{}=ORIENTED_EDGE('',*,*,#{},.T.);\n",
            40 + k,
            d[0] / 10.0,
            d[1] / 10.0,
            44 + k,
            40 + k,
            48 + k,
            20 + a,
            44 + k,
            52 + k,
            30 + a,
            30 + b,
            48 + k,
            56 + k,
            52 + k
        );
    }
    data += &format!(
        "#60=EDGE_LOOP('',(#56,#57,#58,#59));#61=FACE_OUTER_BOUND('',#60,.T.);#{face}=ADVANCED_FACE('',(#61),#{surf},.T.);\n"
    );
    data
}

#[test]
fn offset_and_trimmed_planes() {
    // Plane z = 0 offset by 3: the face at z = 3; a rectangular trimmed
    // surface on it is the same plane.
    let data = format!(
        "{AXIS}#5=PLANE('',#4);#6=OFFSET_SURFACE('',#5,3.,.F.);\
#7=RECTANGULAR_TRIMMED_SURFACE('',#6,0.,10.,0.,10.,.T.,.T.);\n{}",
        square_face(3.0, 7, 70)
    );
    let imp = import(&data);
    assert!(imp.diagnostics.is_empty(), "{:?}", imp.diagnostics);
    let s = &imp.workpiece.surfaces[0];
    for uv in &s.trim.as_ref().expect("trim").outer {
        assert!((eval(s, uv[0], uv[1])[2] - 3.0).abs() < 1e-12);
    }
    for row in &s.control_points {
        for c in row {
            assert!((c[2] - 3.0).abs() < 1e-12);
        }
    }
}

#[test]
fn oriented_face_flips_the_normal() {
    let shape = |orientation: &str| {
        format!(
            "{AXIS}#5=PLANE('',#4);\n{}#80=ORIENTED_FACE('',*,#70,{orientation});#81=OPEN_SHELL('',(#80));\
#82=SHELL_BASED_SURFACE_MODEL('',(#81));\n\
#90=PRODUCT('p','p','',());#91=PRODUCT_DEFINITION_FORMATION('','',#90);#92=PRODUCT_DEFINITION('','',#91,$);\
#93=PRODUCT_DEFINITION_SHAPE('','',#92);#94=SHAPE_REPRESENTATION('',(#4,#82),#901);\
#95=SHAPE_DEFINITION_REPRESENTATION(#93,#94);\n",
            square_face(0.0, 5, 70)
        )
    };
    let kept = import(&shape(".T."));
    let flipped = import(&shape(".F."));
    let (a, b) = (&kept.workpiece.surfaces[0], &flipped.workpiece.surfaces[0]);
    assert_eq!(a.control_points, b.control_points);
    assert_ne!(
        a.reversed, b.reversed,
        "ORIENTED_FACE .F. reverses the face"
    );
}

#[test]
fn absurd_coordinates_are_typed_errors_not_panics() {
    let data = format!("{AXIS}#5=PLANE('',#4);\n{}", square_face(0.0, 5, 70)).replace(
        "#21=CARTESIAN_POINT('',(10.0,",
        "#21=CARTESIAN_POINT('',(1.E308,",
    );
    let text = wrap(&data);
    let line = text
        .lines()
        .position(|l| l.contains("#21=CARTESIAN_POINT"))
        .expect("line")
        + 1;
    let col = text
        .lines()
        .nth(line - 1)
        .and_then(|l| l.find("#21="))
        .expect("col")
        + 1;
    let err =
        import_step(&text, "t.step", "t", &ImportOptions::default()).expect_err("no usable face");
    let msg = err.to_string();
    assert!(matches!(err, cmm::cad::CadError::NoFaces { .. }), "{msg}");
    assert!(
        msg.contains(&format!("t.step:{line}:{col}: #21 CARTESIAN_POINT")),
        "{msg}"
    );
    assert!(msg.contains("not finite or beyond"), "{msg}");
    // The same at the point itself: a typed error.
    let e = with_ctx(&data, |ctx| {
        cmm::cad::step::curves::point(ctx, 21, Space::Model)
    })
    .expect_err("rejected");
    assert!(
        matches!(e, cmm::cad::CadError::OutOfRange { entity: 21, .. }),
        "{e}"
    );
}
