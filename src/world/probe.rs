//! The probe's true physics (world side): contact deflection with friction
//! drag, and the deflection sensor with gain/cross-talk, nonlinearity and
//! noise. The host never sees these parameters.
use rand::Rng;

use super::noise::Ziggurat;
use crate::math::{Mat3, Vec3};

/// True probe parameters.
#[derive(Debug, Clone, PartialEq)]
pub struct TrueProbe {
    /// Probe mount to the undeflected ball centre, mm, in the frame of the
    /// machine's tip link (the spindle reference point on a machine without
    /// a head, where it is the probe vector in machine coordinates; the
    /// probe mount of the head otherwise, turned with the head).
    pub probe_vector: Vec3,
    /// Effective tip radius, mm.
    pub tip_radius_mm: f64,
    /// Sensor gain and cross-talk in the probe's own frame: reading = G d
    /// (+ nonlinearity + noise).
    pub gain: Mat3,
    /// Cubic nonlinearity: adds `k |d|^2 d` to the reading, 1/mm^2.
    pub cubic_per_mm2: f64,
    /// Sensor noise (standard deviation per axis), mm.
    pub noise_mm: f64,
    /// Friction coefficient: tangential drag = mu x normal deflection,
    /// against the motion.
    pub friction: f64,
    /// Mechanical range of the stylus, mm: beyond it the machine reports
    /// the probe over its range, and the stylus, held at its stop, gives
    /// way on its crash protection (a kinematic seat), so the sensor sees
    /// no more than the range however far the machine runs on.
    pub max_deflection_mm: f64,
    /// The stylus shaft and the probe body.
    pub shape: ProbeShape,
}

/// The probe's shape beyond the ball. The stylus shaft is a cylinder along
/// the stylus from the ball centre to the probe mount (the end of the probe
/// vector), outside the ball from where it leaves the ball; the probe body
/// a cylinder from the mount on, away from the ball. A scanning probe's
/// stylus moves as a whole with its deflection: the shaft moves with the
/// ball, the body stays.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProbeShape {
    /// Radius of the stylus shaft, mm.
    pub shaft_radius_mm: f64,
    /// Radius of the probe body, mm.
    pub body_radius_mm: f64,
    /// Length of the probe body from the mount, mm.
    pub body_length_mm: f64,
}

impl ProbeShape {
    /// The shape of a common probe with a ball of `tip_radius_mm`: a shaft
    /// of half the ball's diameter (a 1.5 mm stem on a 3 mm ball; the part
    /// program's default), a body of 25 mm diameter and 80 mm length.
    pub fn common(tip_radius_mm: f64) -> ProbeShape {
        ProbeShape {
            shaft_radius_mm: tip_radius_mm * 0.5,
            body_radius_mm: 12.5,
            body_length_mm: 80.0,
        }
    }
}

impl TrueProbe {
    /// A perfect probe with the nominal geometry (`--ideal`) and the
    /// [`ProbeShape::common`] shaft and body.
    pub fn ideal(probe_vector: Vec3, tip_radius_mm: f64) -> TrueProbe {
        TrueProbe {
            probe_vector,
            tip_radius_mm,
            gain: Mat3::identity(),
            cubic_per_mm2: 0.0,
            noise_mm: 0.0,
            friction: 0.0,
            max_deflection_mm: 1.0,
            shape: ProbeShape::common(tip_radius_mm),
        }
    }

    /// A realistic uncalibrated probe, as the world knows it while the host
    /// assumes the nominal values. The errors are of the size a probe
    /// qualification on a reference sphere has to remove:
    /// - probe vector off by (+3.0, -2.0, +6.0) um (stylus length and
    ///   mounting tolerance);
    /// - effective tip radius 1.2 um below nominal (ball form, stylus
    ///   bending);
    /// - sensor gains 1.006 / 0.994 / 1.004 with cross-talk up to 0.3 %;
    /// - cubic nonlinearity 0.02 / mm^2 (0.5 % at 0.5 mm deflection);
    /// - friction drag 0.04 x the normal deflection against the motion (it
    ///   leans the deflection by 2.3 deg, in opposite senses for clockwise
    ///   and counter-clockwise scans);
    /// - 0.1 um sensor noise per axis.
    pub fn realistic(probe_vector: Vec3, tip_radius_mm: f64) -> TrueProbe {
        TrueProbe {
            probe_vector: probe_vector + Vec3::new(0.0030, -0.0020, 0.0060),
            tip_radius_mm: tip_radius_mm - 0.0012,
            gain: Mat3::new(
                1.006, 0.003, -0.001, -0.002, 0.994, 0.0015, 0.001, -0.002, 1.004,
            ),
            cubic_per_mm2: 0.02,
            noise_mm: 1e-4,
            friction: 0.04,
            ..TrueProbe::ideal(probe_vector, tip_radius_mm)
        }
    }

    /// True ball displacement for penetration `depth = r - s` (mm) along the
    /// surface normal `n`, with friction drag against the tangential motion
    /// `velocity`.
    pub fn deflection(&self, depth: f64, n: Vec3, velocity: Vec3) -> Vec3 {
        if depth <= 0.0 {
            return Vec3::zeros();
        }
        let tangential = velocity - n * velocity.dot(&n);
        let drag = tangential
            .try_normalize(1e-9)
            .map_or(Vec3::zeros(), |t| -t * (self.friction * depth));
        n * depth + drag
    }

    /// The deflection `d` the sensor sees: `d` itself within the stylus's
    /// mechanical range, else `d` shortened to the range (the stylus at
    /// its stop, its seat given way).
    #[inline]
    pub fn within_range(&self, d: Vec3) -> Vec3 {
        let range = self.max_deflection_mm;
        if d.norm_squared() <= range * range {
            d
        } else {
            d * (range / d.norm())
        }
    }

    /// The sensor's noise-free response to a true deflection `d` (gain,
    /// cross-talk and nonlinearity).
    #[inline]
    pub fn response(&self, d: Vec3) -> Vec3 {
        self.gain * d + d * (self.cubic_per_mm2 * d.norm_squared())
    }

    /// The sensor reading of a true deflection `d`: [`Self::response`]
    /// plus noise (none drawn for a zero deflection).
    #[inline(always)]
    pub fn sense(&self, d: Vec3, rng: &mut impl Rng) -> Vec3 {
        let mut reading = self.response(d);
        if self.noise_mm > 0.0 && d.norm_squared() > 0.0 {
            // Positive sigma: the draws need no zero check.
            let (normal, sigma) = (Ziggurat::new(), self.noise_mm);
            let x = sigma * normal.standard_normal(rng);
            let y = sigma * normal.standard_normal(rng);
            let z = sigma * normal.standard_normal(rng);
            reading += Vec3::new(x, y, z);
        }
        reading
    }
}
