//! Servo loop: limits every cycle, analytic first-order response, travel
//! limits, seeded scale readings.
use cmm::machine::builtin::BRIDGE_AB_HEAD_URDF;
use cmm::machine::{MachineModel, MachineProfile};
use cmm::world::dynamics::{Servo, ServoError};
use rand::rngs::ChaCha8Rng;
use rand::{RngExt, SeedableRng};

/// Slack on limit checks for rounding, in mm/s and mm/s^2.
const LIMIT_SLACK: f64 = 1e-9;
/// Agreement with the analytic exponential response, mm and mm/s.
const ANALYTIC_TOL: f64 = 1e-9;

fn bridge_servo(profile: &MachineProfile, start: [f64; 3]) -> Servo {
    Servo::new(&MachineModel::default_bridge(), profile, &start).unwrap()
}

#[test]
fn velocity_and_acceleration_limits_hold_every_cycle() {
    let profile = MachineProfile::default();
    let mut servo = bridge_servo(&profile, [500.0, 350.0, 300.0]);
    let dt = servo.cycle_s();
    let (v_max, a_max) = (
        profile.linear.max_velocity_mm_s,
        profile.linear.max_acceleration_mm_s2,
    );
    let (mut saw_v_max, mut saw_a_max) = (false, false);
    let commands = [
        [-900.0, 900.0, 40.0],
        [900.0, -900.0, -40.0],
        [0.0, 0.0, 0.0],
    ];
    let mut previous = servo.state().velocity;
    for command in commands {
        for _ in 0..350 {
            let state = servo.step(&command).unwrap();
            for (v, v0) in state.velocity.iter().zip(&previous) {
                assert!(v.abs() <= v_max + LIMIT_SLACK, "speed {v}");
                let a = (v - v0).abs() / dt;
                assert!(a <= a_max + LIMIT_SLACK, "acceleration {a}");
                saw_v_max |= v.abs() > v_max - 1e-6;
                saw_a_max |= a > a_max - 1e-6;
            }
            previous = state.velocity;
        }
    }
    assert!(saw_v_max && saw_a_max, "the limits were never reached");
}

#[test]
fn unclamped_step_response_is_the_first_order_exponential() {
    let profile = MachineProfile::default();
    let tau = profile.linear.servo_lag_s;
    // Initial acceleration v/tau = 1600 mm/s^2 stays below the 2000 limit.
    let v = 8.0;
    let mut servo = bridge_servo(&profile, [100.0, 100.0, 100.0]);
    for k in 1..=100 {
        let state = servo.step(&[0.0, v, -v]).unwrap();
        let t = k as f64 * servo.cycle_s();
        let decay = (-t / tau).exp();
        let (vel, dist) = (v * (1.0 - decay), v * (t - tau * (1.0 - decay)));
        assert!((state.time_s - t).abs() < 1e-12);
        assert!((state.velocity[1] - vel).abs() < ANALYTIC_TOL, "cycle {k}");
        assert!(
            (state.position[1] - (100.0 + dist)).abs() < ANALYTIC_TOL,
            "cycle {k}"
        );
        assert!(
            (state.position[2] - (100.0 - dist)).abs() < ANALYTIC_TOL,
            "cycle {k}"
        );
        assert_eq!(state.position[0], 100.0);
    }
}

#[test]
fn leaving_the_travel_range_halts_with_axis_limit() {
    let mut servo = bridge_servo(&MachineProfile::default(), [10.0, 699.0, 5.0]);
    let outcome = (0..1000).find_map(|_| servo.step(&[0.0, 100.0, -1.0]).err());
    match outcome {
        Some(ServoError::AxisLimit {
            axis,
            index,
            position,
            lower,
            upper,
        }) => {
            assert_eq!((axis.as_str(), index, lower, upper), ("x", 1, 0.0, 700.0));
            assert!(position > 700.0 && position < 700.2, "{position}");
        }
        other => panic!("expected an axis limit, got {other:?}"),
    }
    let state = servo.state();
    assert_eq!(state.position[1], 700.0);
    assert!(state.velocity.iter().all(|v| *v == 0.0));
    assert!(
        servo.step(&[0.0, -10.0, 0.0]).is_ok(),
        "can move back inside"
    );
}

#[test]
fn bad_starts_and_commands_are_typed_errors() {
    let model = MachineModel::default_bridge();
    let profile = MachineProfile::default();
    let outside = Servo::new(&model, &profile, &[0.0, -1.0, 0.0]).unwrap_err();
    assert!(
        matches!(outside, ServoError::AxisLimit { index: 1, position, .. } if position == -1.0)
    );
    let short = Servo::new(&model, &profile, &[0.0]).unwrap_err();
    assert_eq!(
        short,
        ServoError::AxisCount {
            expected: 3,
            found: 1
        }
    );
    let mut servo = bridge_servo(&profile, [1.0, 1.0, 1.0]);
    assert_eq!(
        servo.step(&[1.0, 2.0]).unwrap_err(),
        ServoError::AxisCount {
            expected: 3,
            found: 2
        }
    );
    let nan = servo.step(&[0.0, f64::NAN, 0.0]).unwrap_err();
    assert!(matches!(nan, ServoError::NotFinite { index: 1, .. }));
}

#[test]
fn speed_limit_is_the_smaller_of_urdf_and_profile() {
    let model = MachineModel::from_urdf_str(BRIDGE_AB_HEAD_URDF, "ab.urdf").unwrap();
    let text = r#"{"linear": {"max_velocity_mm_s": 800}, "rotary": {"max_velocity_rad_s": 0.5}}"#;
    let profile = MachineProfile::from_json_str(text, "p.json").unwrap();
    let servo = Servo::new(&model, &profile, &[0.0, 0.0, 0.0, 0.0, 0.0]).unwrap();
    let limits: Vec<f64> = servo.axes().iter().map(|a| a.max_velocity).collect();
    assert_eq!(limits, [500.0, 500.0, 500.0, 0.5, 0.5]);
}

/// Scale readings over a short move, with the given profile and seed.
fn readings(profile: &MachineProfile, seed: u64) -> Vec<Vec<f64>> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut servo = bridge_servo(profile, [200.0, 300.0, 400.0]);
    (0..50)
        .map(|_| {
            servo.step(&[20.0, -30.0, 5.0]).unwrap();
            servo.read_scales(&mut rng)
        })
        .collect()
}

#[test]
fn same_seed_same_readings_other_seed_differs() {
    let profile = MachineProfile::default();
    assert_eq!(readings(&profile, 11), readings(&profile, 11));
    assert_ne!(readings(&profile, 11), readings(&profile, 12));
}

#[test]
fn readings_are_quantised_and_near_the_truth() {
    let profile = MachineProfile::default();
    let (res, sigma) = (
        profile.linear.scale_resolution_mm,
        profile.linear.scale_noise_mm,
    );
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mut servo = bridge_servo(&profile, [200.0, 300.0, 400.0]);
    for _ in 0..200 {
        let truth = servo.step(&[20.0, -30.0, 5.0]).unwrap().position;
        for (r, t) in servo.read_scales(&mut rng).iter().zip(&truth) {
            let quanta = r / res;
            assert!(
                (quanta - quanta.round()).abs() < 1e-6,
                "{r} not on the {res} mm grid"
            );
            assert!((r - t).abs() <= res / 2.0 + 6.0 * sigma, "{r} vs {t}");
        }
    }
}

#[test]
fn ideal_profile_reads_exact_positions_and_draws_nothing() {
    let ideal = MachineProfile::default().ideal();
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let mut servo = bridge_servo(&ideal, [200.0, 300.0, 400.0]);
    for _ in 0..100 {
        let truth = servo.step(&[20.0, -30.0, 5.0]).unwrap().position;
        assert_eq!(servo.read_scales(&mut rng), truth);
    }
    let mut fresh = ChaCha8Rng::seed_from_u64(9);
    assert_eq!(rng.random::<u64>(), fresh.random::<u64>());
}

#[test]
fn rotary_head_axis_hits_its_limit_in_radians() {
    let model = MachineModel::from_urdf_str(BRIDGE_AB_HEAD_URDF, "ab.urdf").unwrap();
    let start = [300.0, 300.0, 300.0, 0.0, 0.002];
    let mut servo = Servo::new(&model, &MachineProfile::default(), &start).unwrap();
    let outcome = (0..500).find_map(|_| servo.step(&[0.0, 0.0, 0.0, 0.5, -0.2]).err());
    match outcome {
        Some(ServoError::AxisLimit {
            axis,
            index,
            position,
            lower,
            ..
        }) => {
            assert_eq!((axis.as_str(), index, lower), ("a", 4, 0.0));
            assert!(position < 0.0 && position > -1e-3, "{position}");
        }
        other => panic!("expected the A axis limit, got {other:?}"),
    }
    let b = servo.state().position[3];
    assert!(b > 0.0, "B turned meanwhile: {b}");
}
