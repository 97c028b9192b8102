//! Forward kinematics of URDF machines against hand-computed poses.
use cmm::machine::builtin::BRIDGE_AB_HEAD_URDF;
use cmm::machine::{AxisKind, MachineError, MachineModel};
use cmm::math::{Mat3, Vec3};

/// Agreement of poses computed two ways, mm (and dimensionless for rotations).
const TOL: f64 = 1e-9;

fn rot_x(a: f64) -> Mat3 {
    let (s, c) = a.sin_cos();
    Mat3::new(1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c)
}

fn rot_y(a: f64) -> Mat3 {
    let (s, c) = a.sin_cos();
    Mat3::new(c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c)
}

fn rot_z(a: f64) -> Mat3 {
    let (s, c) = a.sin_cos();
    Mat3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
}

fn ab_head() -> MachineModel {
    MachineModel::from_urdf_str(BRIDGE_AB_HEAD_URDF, "bridge-ab-head.urdf").unwrap()
}

#[test]
fn default_bridge_axes_are_in_mm() {
    let m = MachineModel::default_bridge();
    let names: Vec<&str> = m.axes().iter().map(|a| a.name.as_str()).collect();
    assert_eq!(names, ["y", "x", "z"]);
    let uppers: Vec<f64> = m.axes().iter().map(|a| a.limits.upper).collect();
    assert_eq!(uppers, [1000.0, 700.0, 600.0]);
    for axis in m.axes() {
        assert_eq!(axis.kind, AxisKind::Prismatic);
        assert_eq!(axis.limits.lower, 0.0);
        assert_eq!(axis.limits.velocity, 500.0);
    }
    assert_eq!((m.base_link(), m.tip_link()), ("table", "spindle"));
}

#[test]
fn prismatic_chain_translates_by_axis_values() {
    let m = MachineModel::default_bridge();
    let pose = m.pose(&[250.0, 100.0, 300.0]).unwrap();
    assert!((pose.translation.vector - Vec3::new(100.0, 250.0, 300.0)).norm() < TOL);
    assert!(pose.rotation.angle() < TOL);
    assert_eq!(
        m.linear_xyz(&[250.0, 100.0, 300.0]).unwrap(),
        [100.0, 250.0, 300.0]
    );
}

#[test]
fn wrong_number_of_axis_values_is_an_error() {
    let m = MachineModel::default_bridge();
    let err = m.pose(&[1.0, 2.0]).unwrap_err();
    assert!(matches!(
        err,
        MachineError::AxisCount {
            expected: 3,
            found: 2
        }
    ));
}

#[test]
fn ab_head_rotates_probe_vector_like_rz_times_rx() {
    let m = ab_head();
    assert_eq!(m.axis_index("b"), Some(3));
    assert_eq!(m.axis_index("a"), Some(4));
    let (x, y, z) = (120.0, 340.0, 410.0);
    let stylus = Vec3::new(0.0, 0.0, -50.0);
    for (a, b) in [(0.3, -1.1), (1.2, 2.5), (0.0, 0.7), (1.8, -3.0)] {
        let pose = m.pose(&[y, x, z, b, a]).unwrap();
        let r = rot_z(b) * rot_x(a);
        let rotation = pose.rotation.to_rotation_matrix().into_inner();
        assert!((rotation - r).norm() < TOL, "a {a} b {b}");
        // Spindle -> B centre 50 mm down, -> A centre 30 mm down, mount 20 mm.
        let expected_tip = Vec3::new(x, y, z - 80.0) + r * Vec3::new(0.0, 0.0, -20.0) + r * stylus;
        let tip = pose * cmm::math::Point3::from(stylus);
        assert!((tip.coords - expected_tip).norm() < TOL, "a {a} b {b}");
    }
}

#[test]
fn ab_head_at_right_angles_points_the_stylus_along_minus_x() {
    let m = ab_head();
    let half_pi = std::f64::consts::FRAC_PI_2;
    let pose = m.pose(&[0.0, 200.0, 300.0, half_pi, half_pi]).unwrap();
    let tip = pose * cmm::math::Point3::new(0.0, 0.0, -50.0);
    // A tilts -z to +y, B turns +y to -x: 20 + 50 mm along -x, 80 mm below.
    assert!((tip.coords - Vec3::new(130.0, 0.0, 220.0)).norm() < TOL);
}

#[test]
fn origin_rpy_follows_urdf_fixed_axis_convention_and_metres() {
    let (r, p, yw) = (0.3, -0.2, 0.9);
    let text = format!(
        r#"<robot name="t"><link name="a"/><link name="b"/><link name="c"/>
        <joint name="offset" type="fixed"><parent link="a"/><child link="b"/>
          <origin xyz="0.1 -0.2 0.05" rpy="{r} {p} {yw}"/></joint>
        <joint name="u" type="prismatic"><parent link="b"/><child link="c"/>
          <axis xyz="1 0 0"/><limit lower="-0.5" upper="0.5" velocity="0.2"/></joint>
        </robot>"#
    );
    let m = MachineModel::from_urdf_str(&text, "t.urdf").unwrap();
    let expected_r = rot_z(yw) * rot_y(p) * rot_x(r);
    let u = 40.0;
    let expected_t = Vec3::new(100.0, -200.0, 50.0) + expected_r * Vec3::new(u, 0.0, 0.0);
    let pose = m.pose(&[u]).unwrap();
    assert!((pose.translation.vector - expected_t).norm() < TOL);
    assert!((pose.rotation.to_rotation_matrix().into_inner() - expected_r).norm() < TOL);
    let axis = &m.axes()[0];
    assert_eq!(
        (axis.limits.lower, axis.limits.upper, axis.limits.velocity),
        (-500.0, 500.0, 200.0)
    );
    assert!((axis.home_direction - expected_r * Vec3::x()).norm() < TOL);
}

#[test]
fn shipped_example_file_matches_the_embedded_text() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/part-programs/machines/bridge-ab-head.urdf"
    );
    assert_eq!(std::fs::read_to_string(path).unwrap(), BRIDGE_AB_HEAD_URDF);
    let m = MachineModel::from_urdf_file(path).unwrap();
    assert_eq!(m.axes().len(), 5);
    assert_eq!(m.tip_link(), "probe_mount");
    let a = &m.axes()[4];
    assert_eq!(a.kind, AxisKind::Revolute);
    assert!((a.limits.upper - 105f64.to_radians()).abs() < 1e-12);
}
