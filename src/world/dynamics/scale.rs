//! Scale readings: an axis position plus the scale's Gaussian noise,
//! quantised to the scale's resolution (halves away from zero).
use rand::Rng;

use super::servo::AxisDynamics;
use crate::world::noise::Ziggurat;

impl AxisDynamics {
    /// A scale reading of `position`: plus Gaussian noise, then quantised.
    #[inline]
    pub(super) fn read(&self, position: f64, rng: &mut impl Rng, normal: Ziggurat) -> f64 {
        let noisy = position + normal.gaussian(rng, self.noise_sigma);
        if self.resolution > 0.0 {
            round_half_away(noisy / self.resolution) * self.resolution
        } else {
            noisy
        }
    }
}

/// `q.round()` (halves away from zero) without the libm call on targets
/// without SSE4.1, and without branches: below 2^52, adding and
/// subtracting 2^52 rounds `|q|` to the nearest integer with ties to even
/// (exactly); a tie that went down (`|q| - n = 0.5`) goes up instead, and
/// the sign of `q` comes back (a zero result keeps it, as `f64::round`
/// does). From 2^52 on (where every f64 is an integer) and for NaN,
/// `f64::round` itself.
#[inline]
fn round_half_away(q: f64) -> f64 {
    const EXACT: f64 = 4_503_599_627_370_496.0; // 2^52
    let a = q.abs();
    if a.is_nan() || a >= EXACT {
        return q.round();
    }
    let n = (a + EXACT) - EXACT;
    let up = if a - n >= 0.5 { 1.0 } else { 0.0 };
    (n + up).copysign(q)
}

#[cfg(test)]
mod tests {
    use super::round_half_away;
    use crate::machine::{MachineModel, MachineProfile};
    use crate::world::dynamics::Servo;
    use crate::world::noise::Ziggurat;
    use rand::SeedableRng;

    /// The readings of the three-axis bridge (read without a loop) are
    /// each axis's reading in axis order from the same stream, bit for
    /// bit, over many cycles of noisy, quantised scales.
    #[test]
    fn three_readings_draw_in_axis_order() {
        let profile = MachineProfile::default();
        let model = MachineModel::default_bridge();
        let start = [500.0, 350.0, 300.0];
        let mut servo =
            Servo::new(&model, &profile, &start).unwrap_or_else(|e| panic!("bridge servo: {e}"));
        let mut rng = rand::rngs::Xoshiro256PlusPlus::seed_from_u64(3);
        let mut reference = rng.clone();
        let normal = Ziggurat::new();
        let mut out = Vec::new();
        for cycle in 0..2000 {
            let command = [40.0, -25.0 + (cycle % 50) as f64, 10.0];
            servo
                .advance(&command)
                .unwrap_or_else(|e| panic!("cycle {cycle}: {e}"));
            servo.read_scales_into(&mut rng, &mut out);
            let axes = servo.axes().iter().zip(servo.position());
            let expected: Vec<u64> = axes
                .map(|(a, p)| a.read(*p, &mut reference, normal).to_bits())
                .collect();
            let found: Vec<u64> = out.iter().map(|r| r.to_bits()).collect();
            assert_eq!(found, expected, "cycle {cycle}");
        }
    }

    /// Bit for bit `f64::round` on halves, near-halves, signs, zeros,
    /// large values and a seeded sweep.
    #[test]
    fn rounding_matches_f64_round() {
        let mut cases = vec![
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.5,
            -1.5,
            2.5,
            -2.5,
            0.49999999999999994,
            -0.49999999999999994,
            4_503_599_627_370_495.5,
            -4_503_599_627_370_495.5,
            4_503_599_627_370_494.5,
            2_251_799_813_685_248.5,
            -2_251_799_813_685_249.5,
            4_503_599_627_370_495.0,
            4_503_599_627_370_496.0,
            0.500_000_000_000_000_1,
            1.499_999_999_999_999_8,
            -0.4,
            -1e-300,
            f64::MIN_POSITIVE,
            f64::NEG_INFINITY,
            1e300,
            -1e300,
            f64::INFINITY,
        ];
        let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
        for _ in 0..100_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let unit = (x >> 11) as f64 / (1u64 << 53) as f64;
            cases.push((unit - 0.5) * 2e7);
            cases.push(((unit - 0.5) * 2e4).round() + 0.5);
        }
        for q in cases {
            assert_eq!(round_half_away(q).to_bits(), q.round().to_bits(), "{q}");
        }
        assert!(round_half_away(f64::NAN).is_nan());
    }
}
