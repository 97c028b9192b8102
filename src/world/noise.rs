//! Seeded noise helpers shared by the world's sensors.
//!
//! All randomness comes from a caller-provided generator; nothing here keeps
//! state, so the same seed gives the same stream of draws.
use rand::{Rng, RngExt};

/// A standard normal draw (mean 0, standard deviation 1) by the Box-Muller
/// transform; consumes exactly two uniform draws.
pub fn standard_normal(rng: &mut impl Rng) -> f64 {
    // `1 - u` lies in (0, 1], so the logarithm is finite.
    let u1: f64 = 1.0 - rng.random::<f64>();
    let u2: f64 = rng.random::<f64>();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

/// A zero-mean Gaussian draw with standard deviation `sigma` (same unit as
/// `sigma`). Draws nothing and returns exactly 0 when `sigma` is 0, so an
/// ideal sensor leaves the random stream untouched.
pub fn gaussian(rng: &mut impl Rng, sigma: f64) -> f64 {
    if sigma == 0.0 {
        0.0
    } else {
        sigma * standard_normal(rng)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn standard_normal_has_unit_moments() {
        let mut rng = rand::rngs::ChaCha8Rng::seed_from_u64(7);
        let n = 20_000;
        let draws: Vec<f64> = (0..n).map(|_| standard_normal(&mut rng)).collect();
        let mean = draws.iter().sum::<f64>() / n as f64;
        let var = draws.iter().map(|d| (d - mean).powi(2)).sum::<f64>() / n as f64;
        // 5 standard errors: 5/sqrt(n) for the mean, 5*sqrt(2/n) for the variance.
        assert!(mean.abs() < 5.0 / (n as f64).sqrt(), "mean {mean}");
        assert!(
            (var - 1.0).abs() < 5.0 * (2.0 / n as f64).sqrt(),
            "var {var}"
        );
    }

    #[test]
    fn zero_sigma_draws_nothing() {
        let mut a = rand::rngs::ChaCha8Rng::seed_from_u64(1);
        let mut b = rand::rngs::ChaCha8Rng::seed_from_u64(1);
        assert_eq!(gaussian(&mut a, 0.0), 0.0);
        assert_eq!(a.random::<u64>(), b.random::<u64>());
    }
}
