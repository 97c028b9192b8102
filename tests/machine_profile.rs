//! Machine profile JSON: defaults, JSON-path errors, `ideal()`, and the
//! geometric error at the stylus tip against hand computations (JP2902285B2).
use cmm::machine::{ErrorPolynomial, GeometricErrors, MachineProfile, ProfileError, Stacking};
use cmm::math::Vec3;

const FILE: &str = "machine-profile.json";
/// Agreement of hand-computed and modelled tip displacements, mm.
const TOL_MM: f64 = 1e-12;

fn parse(text: &str) -> Result<MachineProfile, ProfileError> {
    MachineProfile::from_json_str(text, FILE)
}

fn json_path(err: &ProfileError) -> &str {
    match err {
        ProfileError::Syntax(e) => &e.json_path,
        ProfileError::Invalid { json_path, .. } => json_path,
        other => panic!("no JSON path in {other}"),
    }
}

fn poly(c: &[f64]) -> ErrorPolynomial {
    ErrorPolynomial(c.to_vec())
}

#[test]
fn empty_object_gives_the_embedded_defaults() {
    let p = parse("{}").unwrap();
    assert_eq!(p, MachineProfile::default());
    assert_eq!(p.control_cycle_s, 0.001);
    assert_eq!(p.linear.max_velocity_mm_s, 500.0);
    assert_eq!(p.linear.max_acceleration_mm_s2, 2000.0);
    assert_eq!(p.linear.servo_lag_s, 0.005);
    assert_eq!(p.linear.scale_resolution_mm, 1e-4);
    assert_eq!(p.geometric, GeometricErrors::default());
    assert_eq!(p.geometric.stacking, Stacking::Yxz);
}

#[test]
fn given_values_override_defaults() {
    let text = r#"{"linear": {"max_acceleration_mm_s2": 1500},
                   "geometric": {"y": {"pitch_rad": [1e-6, 2e-9]}, "stacking": "xyz"}}"#;
    let p = parse(text).unwrap();
    assert_eq!(p.linear.max_acceleration_mm_s2, 1500.0);
    assert_eq!(p.linear.max_velocity_mm_s, 500.0);
    assert_eq!(p.geometric.y.pitch_rad, poly(&[1e-6, 2e-9]));
    assert_eq!(p.geometric.stacking, Stacking::Xyz);
}

#[test]
fn unknown_keys_and_wrong_types_carry_json_paths() {
    let cases = [
        (r#"{"linear": {"max_speed": 1}}"#, "$.linear.max_speed"),
        (
            r#"{"rotary": {"servo_lag_s": "fast"}}"#,
            "$.rotary.servo_lag_s",
        ),
        (
            r#"{"geometric": {"z": {"roll_rad": [0, "a"]}}}"#,
            "$.geometric.z.roll_rad[1]",
        ),
        (
            r#"{"geometric": {"stacking": "xxz"}}"#,
            "$.geometric.stacking",
        ),
        (r#"{"colour": "red"}"#, "$.colour"),
    ];
    for (text, path) in cases {
        let err = parse(text).unwrap_err();
        assert!(matches!(err, ProfileError::Syntax { .. }), "{err}");
        assert_eq!(json_path(&err), path, "{err}");
        assert!(err.to_string().contains(FILE));
    }
}

#[test]
fn out_of_range_numbers_carry_json_paths_and_values() {
    let cases = [
        (r#"{"control_cycle_s": 0}"#, "$.control_cycle_s", 0.0),
        (
            r#"{"linear": {"max_acceleration_mm_s2": -5}}"#,
            "$.linear.max_acceleration_mm_s2",
            -5.0,
        ),
        (
            r#"{"linear": {"servo_lag_s": -0.001}}"#,
            "$.linear.servo_lag_s",
            -0.001,
        ),
        (
            r#"{"rotary": {"scale_noise_rad": -1}}"#,
            "$.rotary.scale_noise_rad",
            -1.0,
        ),
        (
            r#"{"rotary": {"max_velocity_rad_s": 0}}"#,
            "$.rotary.max_velocity_rad_s",
            0.0,
        ),
    ];
    for (text, path, bad) in cases {
        let err = parse(text).unwrap_err();
        match &err {
            ProfileError::Invalid {
                json_path, value, ..
            } => {
                assert_eq!((json_path.as_str(), *value), (path, bad));
            }
            other => panic!("unexpected {other}"),
        }
        assert!(err.to_string().contains(path));
    }
}

#[test]
fn wrong_format_tag_is_rejected() {
    let err = parse(r#"{"format": "cmm-machine-profile/9"}"#).unwrap_err();
    assert!(matches!(&err, ProfileError::Format { found, .. } if found == "cmm-machine-profile/9"));
}

#[test]
fn schema_lists_the_sections() {
    let schema = serde_json::to_value(MachineProfile::json_schema()).unwrap();
    let props = &schema["properties"];
    for key in ["control_cycle_s", "linear", "rotary", "geometric", "format"] {
        assert!(props.get(key).is_some(), "missing {key}");
    }
}

fn with_errors(edit: impl FnOnce(&mut GeometricErrors)) -> MachineProfile {
    let mut p = MachineProfile::default();
    edit(&mut p.geometric);
    p
}

fn assert_close(a: Vec3, b: Vec3) {
    assert!((a - b).norm() <= TOL_MM, "{a:?} vs {b:?}");
}

#[test]
fn scale_and_straightness_add_directly() {
    let p = with_errors(|g| {
        g.x.scale_mm = poly(&[0.0, 5e-6]);
        g.x.straightness_2_mm = poly(&[1e-3, 0.0, -2e-9]);
        g.z.straightness_1_mm = poly(&[0.0, 1e-6]);
    });
    let d = p.geometric_error([400.0, 200.0, 300.0], &Vec3::new(0.0, 0.0, -50.0));
    // x: 5e-6 * 400 + z straightness along x 1e-6 * 300; z: 1e-3 - 2e-9 * 400^2.
    assert_close(d, Vec3::new(2e-3 + 3e-4, 0.0, 1e-3 - 3.2e-4));
}

#[test]
fn x_pitch_acts_through_ram_extension_and_probe() {
    let p = with_errors(|g| g.x.pitch_rad = poly(&[1e-5]));
    let d = p.geometric_error([100.0, 200.0, 300.0], &Vec3::new(0.0, 0.0, -50.0));
    // Rotation about Y by 1e-5 of the lever (0, 0, 300 - 50): x += 1e-5 * 250.
    assert_close(d, Vec3::new(2.5e-3, 0.0, 0.0));
}

#[test]
fn ram_roll_acts_only_through_the_probe_vector() {
    let p = with_errors(|g| g.z.roll_rad = poly(&[1e-4]));
    let vertical = p.geometric_error([100.0, 200.0, 300.0], &Vec3::new(0.0, 0.0, -50.0));
    assert_close(vertical, Vec3::zeros());
    let sideways = p.geometric_error([100.0, 200.0, 300.0], &Vec3::new(30.0, 0.0, -50.0));
    // (0, 0, 1e-4) x (30, 0, -50) = (0, 3e-3, 0).
    assert_close(sideways, Vec3::new(0.0, 3e-3, 0.0));
}

#[test]
fn bridge_yaw_acts_through_carried_x_and_z() {
    let p = with_errors(|g| g.y.yaw_rad = poly(&[0.0, 1e-8]));
    let d = p.geometric_error([100.0, 500.0, 300.0], &Vec3::new(0.0, 0.0, -50.0));
    // theta_z = 1e-8 * 500 = 5e-6 about Z; lever (100, 0, 250): y += 5e-6 * 100.
    assert_close(d, Vec3::new(0.0, 5e-4, 0.0));
}

#[test]
fn squareness_tilts_the_later_axes() {
    let p = with_errors(|g| {
        g.squareness.xy_rad = 2e-6;
        g.squareness.xz_rad = -1e-6;
        g.squareness.yz_rad = 3e-6;
    });
    let d = p.geometric_error([100.0, 500.0, 300.0], &Vec3::zeros());
    assert_close(d, Vec3::new(500.0 * 2e-6 - 300.0 * 1e-6, 300.0 * 3e-6, 0.0));
}

#[test]
fn ideal_switches_every_error_and_all_noise_off() {
    let text = r#"{"linear": {"scale_noise_mm": 1e-3, "max_velocity_mm_s": 300},
                   "geometric": {"x": {"roll_rad": [1e-5]}, "squareness": {"xy_rad": 1e-5}}}"#;
    let ideal = parse(text).unwrap().ideal();
    assert_eq!(ideal.geometric, GeometricErrors::default());
    assert_eq!(ideal.linear.scale_noise_mm, 0.0);
    assert_eq!(ideal.linear.scale_resolution_mm, 0.0);
    assert_eq!(ideal.rotary.scale_noise_rad, 0.0);
    assert_eq!(ideal.rotary.scale_resolution_rad, 0.0);
    assert_eq!(ideal.linear.max_velocity_mm_s, 300.0, "dynamics are kept");
    let d = ideal.geometric_error([100.0, 500.0, 300.0], &Vec3::new(10.0, 20.0, -50.0));
    assert_eq!(d, Vec3::zeros());
}

#[test]
fn shipped_example_profile_parses_and_has_errors() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/part-programs/machines/bridge-profile-with-errors.json"
    );
    let p = MachineProfile::from_json_file(path).unwrap();
    assert_eq!(p.geometric.x.scale_mm, poly(&[0.0, 3e-6]));
    // At the far corner the errors add up to micrometres, not millimetres.
    let d = p.geometric_error([700.0, 1000.0, 600.0], &Vec3::new(0.0, 0.0, -50.0));
    assert!(d.norm() > 1e-3 && d.norm() < 0.05, "{d:?}");
    let missing = MachineProfile::from_json_file("/nonexistent/profile.json").unwrap_err();
    assert!(matches!(missing, ProfileError::Io { .. }));
    assert!(missing.to_string().contains("/nonexistent/profile.json"));
}

#[test]
fn small_rotations_match_exact_rigid_rotation_of_the_lever() {
    // Independent reference: rotate the lever arm exactly; the first-order
    // model must agree to O(theta^2 * lever).
    let theta = 2e-5;
    let probe = Vec3::new(20.0, -35.0, -60.0);
    let xyz = [150.0, 420.0, 380.0];
    // X roll (about X): the carriage carries only Z, so lever = (0, 0, z) + P.
    let p = with_errors(|g| g.x.roll_rad = poly(&[theta]));
    let lever = Vec3::new(0.0, 0.0, xyz[2]) + probe;
    let exact = nalgebra::Rotation3::from_axis_angle(&Vec3::x_axis(), theta) * lever - lever;
    let model = p.geometric_error(xyz, &probe);
    assert!(
        (model - exact).norm() <= theta * theta * lever.norm(),
        "{model:?} vs {exact:?}"
    );
    assert!(
        model.norm() > 1e-3,
        "the effect is not negligible: {model:?}"
    );
}
