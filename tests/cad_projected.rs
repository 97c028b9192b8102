//! Projection-based trims of B-spline faces without PCURVEs, on a rational
//! B-spline cylinder (radius 10 mm, height 5 mm, seam at u = 0 / 1) whose
//! exact shape is the reference: trim points must map onto the face's
//! circles and seam, and the trim must cover the whole (u, v) domain.
mod cad_common;

use cad_common::{eval, shoelace, wrap};
use cmm::cad::{step::import_step, DiagnosticKind, ImportOptions};

/// Agreement of mapped trim points with the exact edges, mm.
const EDGE_TOL_MM: f64 = 1e-6;

/// The cylinder as #100 (control points #101..#118), full circle in u.
fn cylinder() -> String {
    let w = std::f64::consts::FRAC_1_SQRT_2;
    let ring = [
        (10., 0.),
        (10., 10.),
        (0., 10.),
        (-10., 10.),
        (-10., 0.),
        (-10., -10.),
        (0., -10.),
        (10., -10.),
        (10., 0.),
    ];
    let mut s = String::new();
    let mut rows = Vec::new();
    let mut weights = Vec::new();
    for (i, (x, y)) in ring.iter().enumerate() {
        let (a, b) = (101 + 2 * i, 102 + 2 * i);
        s += &format!("#{a}=CARTESIAN_POINT('',({x:?},{y:?},0.));\n");
        s += &format!("#{b}=CARTESIAN_POINT('',({x:?},{y:?},5.));\n");
        rows.push(format!("(#{a},#{b})"));
        let wi = if i % 2 == 1 { w } else { 1.0 };
        weights.push(format!("({wi:?},{wi:?})"));
    }
    s + &format!(
        "#100=(BOUNDED_SURFACE() B_SPLINE_SURFACE(2,1,({}),.UNSPECIFIED.,.T.,.F.,.F.) \
B_SPLINE_SURFACE_WITH_KNOTS((3,2,2,2,3),(2,2),(0.,0.25,0.5,0.75,1.),(0.,1.),.UNSPECIFIED.) \
GEOMETRIC_REPRESENTATION_ITEM() RATIONAL_B_SPLINE_SURFACE(({})) REPRESENTATION_ITEM('') SURFACE());\n",
        rows.join(","),
        weights.join(",")
    )
}

/// Circles at z = 0 (#23) and z = 5 (#33) with vertices at (10, 0, z) (#26, #36),
/// their closed edges #27, #37, and the seam line edge #47 from #26 to #36.
const EDGES: &str = "#1=DIRECTION('',(0.,0.,1.));\n#2=DIRECTION('',(1.,0.,0.));\n\
#20=CARTESIAN_POINT('',(0.,0.,0.));\n#21=AXIS2_PLACEMENT_3D('',#20,#1,#2);\n#23=CIRCLE('',#21,10.);\n\
#25=CARTESIAN_POINT('',(10.,0.,0.));\n#26=VERTEX_POINT('',#25);\n#27=EDGE_CURVE('',#26,#26,#23,.T.);\n\
#30=CARTESIAN_POINT('',(0.,0.,5.));\n#31=AXIS2_PLACEMENT_3D('',#30,#1,#2);\n#33=CIRCLE('',#31,10.);\n\
#35=CARTESIAN_POINT('',(10.,0.,5.));\n#36=VERTEX_POINT('',#35);\n#37=EDGE_CURVE('',#36,#36,#33,.T.);\n\
#44=VECTOR('',#1,5.);\n#45=LINE('',#25,#44);\n#47=EDGE_CURVE('',#26,#36,#45,.T.);\n";

#[test]
fn seam_loop_becomes_the_whole_domain() {
    let data = format!(
        "{}{EDGES}#51=ORIENTED_EDGE('',*,*,#27,.T.);\n#52=ORIENTED_EDGE('',*,*,#47,.T.);\n\
#53=ORIENTED_EDGE('',*,*,#37,.F.);\n#54=ORIENTED_EDGE('',*,*,#47,.F.);\n\
#55=EDGE_LOOP('',(#51,#52,#53,#54));\n#56=FACE_OUTER_BOUND('',#55,.T.);\n\
#60=ADVANCED_FACE('wall',(#56),#100,.T.);\n",
        cylinder()
    );
    let imp = import_step(&wrap(&data), "t.step", "t", &ImportOptions::default()).unwrap();
    assert!(imp.diagnostics.is_empty(), "{:?}", imp.diagnostics);
    let s = &imp.workpiece.surfaces[0];
    let trim = s.trim.as_ref().unwrap();
    assert!(
        (shoelace(&trim.outer) - 1.0).abs() < 1e-6,
        "area {}",
        shoelace(&trim.outer)
    );
    for uv in &trim.outer {
        let p = eval(s, uv[0], uv[1]);
        let on_circle = (p[0].hypot(p[1]) - 10.0).abs() < EDGE_TOL_MM
            && (p[2].abs() < EDGE_TOL_MM || (p[2] - 5.0).abs() < EDGE_TOL_MM);
        let on_seam = (p[0] - 10.0).abs() < EDGE_TOL_MM && p[1].abs() < EDGE_TOL_MM;
        assert!(on_circle || on_seam, "{uv:?} -> {p:?}");
    }
}

#[test]
fn band_winding_around_the_seam_is_reported_untrimmed() {
    let data = format!(
        "{}{EDGES}#51=ORIENTED_EDGE('',*,*,#27,.T.);\n#55=EDGE_LOOP('',(#51));\n\
#56=FACE_OUTER_BOUND('',#55,.T.);\n#61=ORIENTED_EDGE('',*,*,#37,.F.);\n\
#65=EDGE_LOOP('',(#61));\n#66=FACE_BOUND('',#65,.T.);\n\
#60=ADVANCED_FACE('band',(#56,#66),#100,.T.);\n",
        cylinder()
    );
    let imp = import_step(&wrap(&data), "t.step", "t", &ImportOptions::default()).unwrap();
    assert!(imp.workpiece.surfaces[0].trim.is_none());
    let d = &imp.diagnostics[0];
    assert_eq!(d.kind, DiagnosticKind::Untrimmed);
    assert!(
        d.message.contains("winds around the closed u direction"),
        "{}",
        d.message
    );
}
