//! exploratory
mod common;
use cmm::geometry::{Plane, SectionOptions};
use cmm::math::{Point3, Vec3};
use cmm::workpiece::{section_faces, Workpiece};
use common::*;

#[test]
fn explore() {
    let wp = Workpiece::from_path(&repo("workpieces/nist-ctc05.stp")).unwrap();
    let ids: Vec<usize> = ["face129", "face130", "face131", "face132", "face133"]
        .iter()
        .map(|n| wp.face_index(n).unwrap())
        .collect();
    for &i in &ids {
        let f = &wp.faces[i];
        let s = &f.surface;
        let ((u0, u1), (v0, v1)) = s.domain();
        println!("face {} dom u {u0}..{u1} v {v0}..{v1}", f.name);
        for (u, v) in [(u0, v0), (u1, v0), (u0, v1), (u1, v1), ((u0+u1)/2.0,(v0+v1)/2.0)] {
            println!("   ({u},{v}) -> {:?}", s.point(u, v));
        }
        let vm = (v0+v1)/2.0;
        for u in [0.0, -0.0001478784808432998, 3.14144477510895, std::f64::consts::PI, 1.5706321129645542, std::f64::consts::FRAC_PI_2, 4.712224766554347, 3.0*std::f64::consts::FRAC_PI_2] {
            if u >= u0 && u <= u1 { println!("   u {u} -> {:?}", s.point(u, vm)); }
        }
        if let Some(t) = &f.trim {
            let segs: Vec<_> = t.segments().collect();
            println!("   trim {} segs", segs.len());
            for (a, b) in segs.iter().take(3) {
                println!("     {:?} -> {:?}", a, b);
            }
        }
    }
    let opts = SectionOptions::default();
    for (o, n) in [([0., 0., 0.], [0., 1., 0.]), ([0., 0., 0.], [1., 0., 0.]), ([0., 0.01, 0.], [0., 1., 0.]),
        ([0., 0., 380.], [0., 20f64.to_radians().sin(), 20f64.to_radians().cos()])] {
        let pl = Plane::try_new(Point3::from(o), Vec3::from(n)).unwrap();
        for &i in &ids {
            let cs = section_faces(&wp, &[i], &pl, &opts);
            for c in &cs {
                println!("  plane {o:?} {n:?} face {} : {} pts closed {} len {:.4} {:?} -> {:?}", wp.faces[i].name, c.points.len(), c.closed, c.length(), c.points[0].point, c.points.last().unwrap().point);
            }
        }
        let cs = section_faces(&wp, &ids, &pl, &opts);
        println!("ALL plane {o:?} {n:?}: {} curves, {:?}", cs.len(), cs.iter().map(|c| (c.closed, c.length())).collect::<Vec<_>>());
    }
}
