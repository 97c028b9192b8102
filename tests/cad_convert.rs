//! Exact conversions and trims on synthetic faces: rational arcs, a
//! cylinder band bounded by two full circles, a spherical cap closed at the
//! pole, surfaces of revolution and extrusion.
mod cad_common;
use cad_common::{eval, shoelace, wrap};
use cmm::cad::convert::arc::Arc;
use cmm::cad::{step::import_step, ImportOptions};
use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// Evaluates the unit-circle rational arc at B-spline parameter `u`.
fn arc_point(arc: &Arc, u: f64) -> (f64, f64) {
    let pts = arc.points();
    let spec = cmm::workpiece::format::SurfaceSpec {
        name: "a".into(),
        degree: [2, 1],
        knots_u: arc.knots(),
        knots_v: vec![0.0, 0.0, 1.0, 1.0],
        control_points: pts
            .iter()
            .map(|p| vec![[p.c, p.s, 0.0], [p.c, p.s, 1.0]])
            .collect(),
        weights: Some(pts.iter().map(|p| vec![p.w, p.w]).collect()),
        reversed: false,
        trim: None,
    };
    let p = eval(&spec, u, 0.0);
    (p[0], p[1])
}

#[test]
fn arc_parameter_of_an_angle_is_exact() {
    for (start, end) in [(0.0, TAU), (-0.3, 1.2), (1.0, 1.0 + PI), (2.0, 2.0 + 0.01)] {
        let arc = Arc::new(start, end);
        for k in 0..=50 {
            let angle = start + (end - start) * k as f64 / 50.0;
            let (x, y) = arc_point(&arc, arc.param(angle));
            assert!((x.hypot(y) - 1.0).abs() < 1e-14, "on the circle");
            let back = y.atan2(x);
            let d = (back - angle).rem_euclid(TAU);
            assert!(d.min(TAU - d) < 1e-13, "angle {angle} -> {back}");
        }
    }
}

/// Frame at (0,0,z) with axis +z, a circle of radius r there, a vertex on it
/// at angle 0 and an edge loop of that one closed edge; ids from `base`.
fn circle_loop(base: u32, z: f64, r: f64, bound: &str, forward: &str) -> String {
    let b = base;
    format!(
        "#{b}=CARTESIAN_POINT('',(0.,0.,{z:?}));\n#{b1}=DIRECTION('',(0.,0.,1.));\n#{b2}=DIRECTION('',(1.,0.,0.));\n\
#{b3}=AXIS2_PLACEMENT_3D('',#{b},#{b1},#{b2});\n#{b4}=CIRCLE('',#{b3},{r:?});\n\
#{b5}=CARTESIAN_POINT('',({r:?},0.,{z:?}));\n#{b6}=VERTEX_POINT('',#{b5});\n\
#{b7}=EDGE_CURVE('',#{b6},#{b6},#{b4},.T.);\n#{b8}=ORIENTED_EDGE('',*,*,#{b7},{forward});\n\
#{b9}=EDGE_LOOP('',(#{b8}));\n#{b10}={bound}('',#{b9},.T.);\n",
        b1 = b + 1, b2 = b + 2, b3 = b + 3, b4 = b + 4, b5 = b + 5, b6 = b + 6, b7 = b + 7, b8 = b + 8, b9 = b + 9, b10 = b + 10
    )
}

const AXIS: &str = "#1=CARTESIAN_POINT('',(0.,0.,0.));\n#2=DIRECTION('',(0.,0.,1.));\n#3=DIRECTION('',(1.,0.,0.));\n#4=AXIS2_PLACEMENT_3D('',#1,#2,#3);\n";

fn import(text: &str) -> cmm::cad::Import {
    import_step(text, "t.step", "t", &ImportOptions::default()).expect("imports")
}

#[test]
fn cylinder_band_between_two_full_circles() {
    let data = format!(
        "{AXIS}#5=CYLINDRICAL_SURFACE('',#4,10.);\n{}{}#50=ADVANCED_FACE('band',(#20,#40),#5,.T.);\n",
        circle_loop(10, 0.0, 10.0, "FACE_OUTER_BOUND", ".T."),
        circle_loop(30, 5.0, 10.0, "FACE_BOUND", ".F.")
    );
    let imp = import(&wrap(&data));
    let s = &imp.workpiece.surfaces[0];
    assert!(!s.reversed);
    let trim = s.trim.as_ref().expect("trim");
    assert!(trim.holes.is_empty());
    let (umin, umax) = trim
        .outer
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p[0]), b.max(p[0])));
    assert!(
        umin.abs() < 1e-12 && (umax - TAU).abs() < 1e-12,
        "band spans the full circle: {umin} {umax}"
    );
    assert!(
        (shoelace(&trim.outer).abs() - TAU * 5.0).abs() < 1e-9,
        "area {}",
        shoelace(&trim.outer)
    );
    for uv in &trim.outer {
        let p = eval(s, uv[0], uv[1]);
        assert!((p[0].hypot(p[1]) - 10.0).abs() < 1e-12);
        assert!(p[2].abs() < 1e-12 || (p[2] - 5.0).abs() < 1e-12, "{p:?}");
    }
}

#[test]
fn spherical_cap_closes_at_the_pole() {
    let r_c = 75f64.sqrt();
    let data = format!(
        "{AXIS}#5=SPHERICAL_SURFACE('',#4,10.);\n{}#60=CARTESIAN_POINT('',(0.,0.,10.));\n#61=VERTEX_POINT('',#60);\n\
#62=VERTEX_LOOP('',#61);\n#63=FACE_BOUND('',#62,.T.);\n#70=ADVANCED_FACE('cap',(#20,#63),#5,.T.);\n",
        circle_loop(10, 5.0, r_c, "FACE_OUTER_BOUND", ".T.")
    );
    let imp = import(&wrap(&data));
    let s = &imp.workpiece.surfaces[0];
    let trim = s.trim.as_ref().expect("trim");
    let (mut on_circle, mut at_pole) = (0, 0);
    for uv in &trim.outer {
        let p = eval(s, uv[0], uv[1]);
        assert!(((p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() - 10.0).abs() < 1e-12);
        if (p[2] - 5.0).abs() < 1e-9 {
            on_circle += 1;
        } else if (p[2] - 10.0).abs() < 1e-9 {
            at_pole += 1;
        } else {
            panic!("trim point {p:?} neither on the circle nor at the pole");
        }
    }
    assert!(on_circle > 100 && at_pole == 2, "{on_circle} {at_pole}");
    let vmax = s.knots_v[s.knots_v.len() - 1];
    assert!(
        (vmax - FRAC_PI_2).abs() < 1e-15,
        "patch reaches the pole exactly"
    );
}

#[test]
fn reversed_cap_lies_below_the_circle() {
    // The same circle traversed the other way bounds the lower part of the sphere.
    let data = format!(
        "{AXIS}#5=SPHERICAL_SURFACE('',#4,10.);\n{}#70=ADVANCED_FACE('lower',(#20),#5,.T.);\n",
        circle_loop(10, 5.0, 75f64.sqrt(), "FACE_OUTER_BOUND", ".F.")
    );
    let imp = import(&wrap(&data));
    let s = &imp.workpiece.surfaces[0];
    let trim = s.trim.as_ref().expect("trim");
    let zmin = trim
        .outer
        .iter()
        .map(|uv| eval(s, uv[0], uv[1])[2])
        .fold(f64::MAX, f64::min);
    assert!(
        (zmin + 10.0).abs() < 1e-9,
        "closes at the south pole, got {zmin}"
    );
}

#[test]
fn surface_of_revolution_of_a_circle_is_a_torus() {
    let data = "#1=CARTESIAN_POINT('',(0.,0.,0.));\n#2=DIRECTION('',(0.,0.,1.));\n#3=AXIS1_PLACEMENT('',#1,#2);\n\
#4=CARTESIAN_POINT('',(20.,0.,0.));\n#5=DIRECTION('',(0.,-1.,0.));\n#6=DIRECTION('',(1.,0.,0.));\n\
#7=AXIS2_PLACEMENT_3D('',#4,#5,#6);\n#8=CIRCLE('',#7,3.);\n#9=SURFACE_OF_REVOLUTION('',#8,#3);\n\
#10=ADVANCED_FACE('rev',(),#9,.T.);\n";
    let imp = import(&wrap(data));
    let s = &imp.workpiece.surfaces[0];
    assert!(imp.diagnostics.is_empty());
    let trim = s.trim.as_ref().expect("unbounded face: the whole domain");
    assert_eq!(trim.outer.len(), 4);
    let (u1, v1) = (
        s.knots_u[s.knots_u.len() - 1],
        s.knots_v[s.knots_v.len() - 1],
    );
    for a in 0..=20 {
        for b in 0..=20 {
            let p = eval(s, u1 * a as f64 / 20.0, v1 * b as f64 / 20.0);
            let tube = (p[0].hypot(p[1]) - 20.0).hypot(p[2]);
            assert!((tube - 3.0).abs() < 1e-12, "{p:?}");
        }
    }
}

#[test]
fn linear_extrusion_of_an_ellipse() {
    let data = "#1=CARTESIAN_POINT('',(0.,0.,0.));\n#2=DIRECTION('',(0.,0.,1.));\n#3=DIRECTION('',(1.,0.,0.));\n\
#4=AXIS2_PLACEMENT_3D('',#1,#2,#3);\n#5=ELLIPSE('',#4,4.,2.);\n#6=VECTOR('',#2,1.);\n\
#7=SURFACE_OF_LINEAR_EXTRUSION('',#5,#6);\n#8=CARTESIAN_POINT('',(4.,0.,7.));\n#9=VERTEX_POINT('',#8);\n\
#10=VERTEX_LOOP('',#9);\n#11=FACE_BOUND('',#10,.T.);\n#12=ADVANCED_FACE('ext',(#11),#7,.F.);\n";
    let imp = import(&wrap(data));
    let s = &imp.workpiece.surfaces[0];
    assert!(s.reversed);
    for a in 0..=16 {
        let u = s.knots_u[s.knots_u.len() - 1] * a as f64 / 16.0;
        let p = eval(s, u, s.knots_v[1]);
        assert!(((p[0] / 4.0).powi(2) + (p[1] / 2.0).powi(2) - 1.0).abs() < 1e-14);
    }
    let (v0, v1) = (s.knots_v[0], s.knots_v[3]);
    assert!(
        (v0 - 6.9).abs() < 1e-12 && (v1 - 7.1).abs() < 1e-12,
        "extent from the vertex with 0.1 mm margin: {v0} {v1}"
    );
}

#[test]
fn sampled_circle_edge_meets_the_chord_tolerance() {
    // A disc of radius 50 on the plane z = 0, bounded by one full circle.
    let data = format!(
        "{AXIS}#5=PLANE('',#4);\n{}#70=ADVANCED_FACE('disc',(#20),#5,.T.);\n",
        circle_loop(10, 0.0, 50.0, "FACE_OUTER_BOUND", ".T.")
    );
    let opts = ImportOptions::default();
    let imp = import(&wrap(&data));
    let trim = imp.workpiece.surfaces[0].trim.as_ref().expect("trim");
    let n = trim.outer.len();
    let mut worst: f64 = 0.0;
    for k in 0..n {
        let (a, b) = (trim.outer[k], trim.outer[(k + 1) % n]);
        assert!(
            (a[0].hypot(a[1]) - 50.0).abs() < 1e-12,
            "samples lie on the circle"
        );
        let mid = [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0];
        worst = worst.max(50.0 - mid[0].hypot(mid[1]));
    }
    assert!(worst <= opts.chord_tolerance_mm, "sagitta {worst}");
    assert!(
        worst > opts.chord_tolerance_mm / 8.0,
        "not needlessly dense: {worst} with {n} points"
    );
}

/// A half cylinder made by extruding a half circle (B-spline profile) and a
/// revolved slanted line (a cone frustum), both bounded by real edges: the
/// trims must reproduce the vertices.
#[test]
fn swept_faces_get_trims_through_their_vertices() {
    // Extrusion of the circle x^2 + y^2 = 25 along z, face between z = 0 and z = 4,
    // bounded by two circles (full band).
    let data = format!(
        "{AXIS}#5=CIRCLE('',#4,5.);\n#6=VECTOR('',#2,1.);\n#7=SURFACE_OF_LINEAR_EXTRUSION('',#5,#6);\n{}{}\
#50=ADVANCED_FACE('band',(#20,#40),#7,.T.);\n",
        circle_loop(10, 0.0, 5.0, "FACE_OUTER_BOUND", ".T."),
        circle_loop(30, 4.0, 5.0, "FACE_BOUND", ".F.")
    );
    let imp = import(&wrap(&data));
    let s = &imp.workpiece.surfaces[0];
    let trim = s.trim.as_ref().expect("trim");
    for uv in trim.outer.iter() {
        let p = eval(s, uv[0], uv[1]);
        assert!((p[0].hypot(p[1]) - 5.0).abs() < 1e-12);
        assert!(p[2].abs() < 1e-9 || (p[2] - 4.0).abs() < 1e-9, "{p:?}");
    }
    let (vmin, vmax) = (s.knots_v[0], s.knots_v[3]);
    assert!(
        (vmin + 0.1).abs() < 1e-9 && (vmax - 4.1).abs() < 1e-9,
        "{vmin} {vmax}"
    );
}

#[test]
fn revolved_line_is_bounded_by_its_edges() {
    // The line through (3,0,0) and (5,0,2) revolved about z: a cone frustum
    // between the circles r = 3 at z = 0 and r = 5 at z = 2.
    let data = format!(
        "#1=CARTESIAN_POINT('',(0.,0.,0.));\n#2=DIRECTION('',(0.,0.,1.));\n#3=AXIS1_PLACEMENT('',#1,#2);\n\
#4=CARTESIAN_POINT('',(3.,0.,0.));\n#5=DIRECTION('',(1.,0.,1.));\n#6=VECTOR('',#5,2.);\n#7=LINE('',#4,#6);\n\
#8=SURFACE_OF_REVOLUTION('',#7,#3);\n{}{}#50=ADVANCED_FACE('frustum',(#20,#40),#8,.T.);\n",
        circle_loop(10, 0.0, 3.0, "FACE_OUTER_BOUND", ".T."),
        circle_loop(30, 2.0, 5.0, "FACE_BOUND", ".F.")
    );
    let imp = import(&wrap(&data));
    let s = &imp.workpiece.surfaces[0];
    let trim = s.trim.as_ref().expect("trim");
    let mut levels = [0, 0];
    for uv in &trim.outer {
        let p = eval(s, uv[0], uv[1]);
        let r = p[0].hypot(p[1]);
        assert!((r - (3.0 + p[2])).abs() < 1e-9, "on the cone: {p:?}");
        levels[usize::from(p[2] > 1.0)] += 1;
    }
    assert!(levels[0] > 10 && levels[1] > 10, "{levels:?}");
    let corner = eval(s, s.knots_u[0], s.knots_v[0]);
    assert!(
        (corner[2] + 0.1 / 2f64.sqrt()).abs() < 1e-9,
        "0.1 mm margin along the line: {corner:?}"
    );
}

#[test]
fn rational_complex_surface_in_any_record_order() {
    // A quarter cylinder (radius 2, height 3) as a rational B-spline surface,
    // records deliberately out of the usual order.
    let w = std::f64::consts::FRAC_1_SQRT_2;
    let data = format!(
        "#1=CARTESIAN_POINT('',(2.,0.,0.));\n#2=CARTESIAN_POINT('',(2.,0.,3.));\n\
#3=CARTESIAN_POINT('',(2.,2.,0.));\n#4=CARTESIAN_POINT('',(2.,2.,3.));\n\
#5=CARTESIAN_POINT('',(0.,2.,0.));\n#6=CARTESIAN_POINT('',(0.,2.,3.));\n\
#7=(SURFACE() RATIONAL_B_SPLINE_SURFACE(((1.,1.),({w:?},{w:?}),(1.,1.))) REPRESENTATION_ITEM('') \
B_SPLINE_SURFACE_WITH_KNOTS((3,3),(2,2),(0.,1.),(0.,1.),.UNSPECIFIED.) GEOMETRIC_REPRESENTATION_ITEM() \
B_SPLINE_SURFACE(2,1,((#1,#2),(#3,#4),(#5,#6)),.UNSPECIFIED.,.F.,.F.,.F.) BOUNDED_SURFACE());\n\
#8=ADVANCED_FACE('quarter',(),#7,.T.);\n"
    );
    let imp = import(&wrap(&data));
    assert_eq!(imp.faces[0].surface_type, "RATIONAL_B_SPLINE_SURFACE");
    let s = &imp.workpiece.surfaces[0];
    assert_eq!(s.degree, [2, 1]);
    assert_eq!(s.knots_u, vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0]);
    assert_eq!(s.weights.as_ref().map(|w| w[1][0]), Some(w));
    for k in 0..=10 {
        let p = eval(s, k as f64 / 10.0, 0.5);
        assert!((p[0].hypot(p[1]) - 2.0).abs() < 1e-14 && (p[2] - 1.5).abs() < 1e-14);
    }
    assert_eq!(
        imp.diagnostics.len(),
        1,
        "no PCURVEs: untrimmed, and reported"
    );
}
