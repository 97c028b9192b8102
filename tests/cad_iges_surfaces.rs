//! IGES surface entities against analytic references: 196 sphere points at
//! the radius from the centre, 120 revolutions of lines (cylinder, cone),
//! 122 extrusion of an arc, 118 ruled surfaces, 192 cylinder trimmed by a
//! 144 with model-space boundaries, 408 subfigure instances (nested, with
//! scale and 124 transforms), inch units.
mod cad_iges_support;
use cad_iges_support::{grid_points, run, Iges};

const TOL: f64 = 1e-9;

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

fn only_surface(g: &Iges) -> cmm::workpiece::format::SurfaceSpec {
    let imp = run(&g.text()).expect("imports");
    assert_eq!(imp.workpiece.surfaces.len(), 1, "{:?}", imp.diagnostics);
    assert!(imp.diagnostics.is_empty(), "{:?}", imp.diagnostics);
    imp.workpiece.surfaces[0].clone()
}

#[test]
fn sphere_196_points_lie_at_the_radius() {
    let mut g = Iges::default();
    let c = g.add(116, 0, "1.,2.,3.,0");
    g.dependent(c);
    g.add(196, 0, &format!("{c},5."));
    let s = only_surface(&g);
    let pts = grid_points(&s, 16);
    for p in &pts {
        assert!((dist(*p, [1.0, 2.0, 3.0]) - 5.0).abs() < TOL, "{p:?}");
    }
    let top = pts.iter().map(|p| p[2]).fold(f64::MIN, f64::max);
    let bottom = pts.iter().map(|p| p[2]).fold(f64::MAX, f64::min);
    assert!(
        (top - 8.0).abs() < TOL && (bottom + 2.0).abs() < TOL,
        "whole sphere"
    );
}

#[test]
fn sphere_in_inches_moved_by_a_chained_124() {
    let mut g = Iges::default();
    g.units = "1,2HIN".into();
    // Rotation by 90 deg about z, then a translation by (10, 0, 0) chained on it.
    let shift = g.add(124, 0, "1.,0.,0.,10.,0.,1.,0.,0.,0.,0.,1.,0.");
    let rot = g.add_t(124, 0, "0.,-1.,0.,0.,1.,0.,0.,0.,0.,0.,1.,0.", shift);
    let c = g.add(116, 0, "1.,0.,0.,0");
    g.dependent(c);
    g.add_t(196, 0, &format!("{c},2."), rot);
    let s = only_surface(&g);
    // Centre (1, 0, 0) -> rotated (0, 1, 0) -> shifted (10, 1, 0) in, radius 2 in.
    let centre = [254.0, 25.4, 0.0];
    for p in grid_points(&s, 12) {
        assert!((dist(p, centre) - 50.8).abs() < 1e-8, "{p:?}");
    }
}

fn revolve_line(
    a: [f64; 3],
    b: [f64; 3],
    angles: (f64, f64),
) -> cmm::workpiece::format::SurfaceSpec {
    let mut g = Iges::default();
    let axis = g.add(110, 0, "0.,0.,0.,0.,0.,1.");
    let line = g.add(
        110,
        0,
        &format!("{},{},{},{},{},{}", a[0], a[1], a[2], b[0], b[1], b[2]),
    );
    g.dependent(axis);
    g.dependent(line);
    g.add(120, 0, &format!("{axis},{line},{},{}", angles.0, angles.1));
    only_surface(&g)
}

#[test]
fn revolution_120_of_a_parallel_line_is_a_cylinder() {
    let s = revolve_line(
        [3.0, 0.0, 0.0],
        [3.0, 0.0, 10.0],
        (0.0, std::f64::consts::PI),
    );
    let pts = grid_points(&s, 16);
    for p in &pts {
        assert!((p[0].hypot(p[1]) - 3.0).abs() < TOL, "{p:?}");
        assert!(p[2] > -TOL && p[2] < 10.0 + TOL && p[1] > -TOL, "{p:?}");
    }
    assert!(
        pts.iter().any(|p| (p[0] + 3.0).abs() < TOL),
        "sweeps to 180 deg"
    );
}

#[test]
fn revolution_120_of_a_slanted_line_is_a_cone() {
    let s = revolve_line([2.0, 0.0, 0.0], [4.0, 0.0, 4.0], (0.5, 6.0));
    for p in grid_points(&s, 16) {
        assert!((p[0].hypot(p[1]) - (2.0 + p[2] / 2.0)).abs() < TOL, "{p:?}");
        let a = p[1].atan2(p[0]).rem_euclid(std::f64::consts::TAU);
        assert!(a > 0.5 - 1e-9 && a < 6.0 + 1e-9, "{a}");
    }
}

#[test]
fn tabulated_cylinder_122_of_a_quarter_arc() {
    let mut g = Iges::default();
    let arc = g.add(100, 0, "0.,0.,0.,5.,0.,0.,5.");
    g.dependent(arc);
    g.add(122, 0, &format!("{arc},5.,0.,7."));
    let s = only_surface(&g);
    let pts = grid_points(&s, 16);
    for p in &pts {
        assert!((p[0].hypot(p[1]) - 5.0).abs() < TOL, "{p:?}");
        assert!(p[0] > -TOL && p[1] > -TOL && p[2] > -TOL && p[2] < 7.0 + TOL);
    }
    assert!(pts
        .iter()
        .any(|p| (p[2] - 7.0).abs() < TOL && (p[1] - 5.0).abs() < TOL));
}

#[test]
fn ruled_118_between_coaxial_arcs_is_a_cone() {
    let mut g = Iges::default();
    let a = g.add(100, 0, "0.,0.,0.,2.,0.,0.,2.");
    let b = g.add(100, 0, "4.,0.,0.,3.,0.,0.,3.");
    g.add(118, 1, &format!("{a},{b},0,0"));
    let s = only_surface(&g);
    for p in grid_points(&s, 16) {
        assert!((p[0].hypot(p[1]) - (2.0 + p[2] / 4.0)).abs() < TOL, "{p:?}");
    }
}

#[test]
fn ruled_118_between_a_line_and_a_spline_with_reversal() {
    let mut g = Iges::default();
    let a = g.add(110, 0, "0.,0.,0.,4.,0.,0.");
    // A quadratic B-spline from (4, 0, 3) over (2, 0, 5) to (0, 0, 3): in the y = 0 plane.
    let b = g.add(
        126,
        0,
        "2,2,0,0,1,0,0.,0.,0.,1.,1.,1.,1.,1.,1.,4.,0.,3.,2.,0.,5.,0.,0.,3.,0.,1.,0.,1.,0.",
    );
    g.add(118, 1, &format!("{a},{b},1,0"));
    let s = only_surface(&g);
    for p in grid_points(&s, 16) {
        assert!(p[1].abs() < TOL, "{p:?}");
    }
    let surf = s.to_surface().expect("surface");
    let (p, q) = (surf.point(0.0, 1.0), surf.point(0.0, 0.0));
    assert!(
        (p.x - 0.0).abs() < TOL && (p.z - 3.0).abs() < TOL,
        "reversed rail: {p:?}"
    );
    assert!(q.x.abs() < TOL && q.z.abs() < TOL, "{q:?}");
}

#[test]
fn cylinder_192_trimmed_by_model_space_circles() {
    let mut g = Iges::default();
    let loc = g.add(116, 0, "0.,0.,0.,0");
    let axis = g.add(123, 0, "0.,0.,1.");
    let cyl = g.add(192, 0, &format!("{loc},{axis},4."));
    // Loop: the circle at z = 0 (counter-clockwise), up the seam, the circle
    // at z = 6 clockwise (a reflecting 124: y -> -y, z -> 6 - z), down the seam.
    let lower = g.add(100, 0, "0.,0.,0.,4.,0.,4.,0.");
    let flip = g.add(124, 0, "1.,0.,0.,0.,0.,-1.,0.,0.,0.,0.,-1.,6.");
    let up = g.add(110, 0, "4.,0.,0.,4.,0.,6.");
    let top_back = g.add_t(100, 0, "0.,0.,0.,4.,0.,4.,0.", flip);
    let down = g.add(110, 0, "4.,0.,6.,4.,0.,0.");
    let comp = g.add(102, 0, &format!("4,{lower},{up},{top_back},{down}"));
    let bound = g.add(142, 0, &format!("0,{cyl},0,{comp},2"));
    g.add(144, 0, &format!("{cyl},1,0,{bound}"));
    let imp = run(&g.text()).expect("imports");
    let faces: Vec<_> = imp.workpiece.surfaces.iter().collect();
    assert_eq!(faces.len(), 1, "{:?}", imp.diagnostics);
    let s = faces[0];
    assert!(s.trim.is_some(), "{:?}", imp.diagnostics);
    for p in grid_points(s, 12) {
        assert!((p[0].hypot(p[1]) - 4.0).abs() < TOL, "{p:?}");
        assert!(
            p[2] > -0.2 && p[2] < 6.2,
            "extent of the face plus margin: {p:?}"
        );
    }
}

#[test]
fn subfigure_instances_nest_with_scale_and_transform() {
    let mut g = Iges::default();
    let c = g.add(116, 0, "1.,0.,0.,0");
    let sphere = g.add(196, 0, &format!("{c},1."));
    g.dependent(c);
    g.dependent(sphere);
    let inner = g.add(308, 0, &format!("0,5Hinner,1,{sphere}"));
    // Inner instance: scale 2, shift (0, 5, 0).
    let inst = g.add(408, 0, &format!("{inner},0.,5.,0.,2."));
    g.dependent(inst);
    let outer = g.add(308, 0, &format!("1,5Houter,1,{inst}"));
    // Outer instance: a 124 rotating 90 deg about z, shift (100, 0, 0), scale 3.
    let rot = g.add(124, 0, "0.,-1.,0.,0.,1.,0.,0.,0.,0.,0.,1.,0.");
    g.add_t(408, 0, &format!("{outer},100.,0.,0.,3."), rot);
    let s = only_surface(&g);
    // Centre (1,0,0) -> inner: 2 * (1,0,0) + (0,5,0) = (2,5,0), radius 2
    // -> outer: 3 * (2,5,0) + (100,0,0) = (106,15,0), radius 6 -> rotated: (-15,106,0).
    for p in grid_points(&s, 12) {
        assert!((dist(p, [-15.0, 106.0, 0.0]) - 6.0).abs() < 1e-9, "{p:?}");
    }
}
