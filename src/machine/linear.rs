//! The linear axes of a chain resolved once for the per-cycle simulation:
//! machine X, Y, Z from axis values and axis values from X, Y, Z, without
//! walking the axis metadata every control cycle.
use super::model::{AxisKind, MachineModel};
use crate::math::Vec3;

/// Home directions of a chain's axes, resolved from a [`MachineModel`].
#[derive(Debug, Clone, PartialEq)]
pub struct LinearAxes {
    /// Per axis (chain order): its home direction when it is prismatic.
    directions: Vec<Option<Vec3>>,
    /// Index and home direction of each prismatic axis, chain order.
    prismatic: Vec<(usize, Vec3)>,
    /// The same when there are exactly three (every machine so far), for
    /// a sum without a loop.
    three: Option<[(usize, Vec3); 3]>,
    /// The home directions when the chain is exactly three prismatic axes
    /// (a machine without a head): values and axes then map one to one.
    only_xyz: Option<[Vec3; 3]>,
}

impl LinearAxes {
    /// The linear axes of `model`.
    pub fn new(model: &MachineModel) -> LinearAxes {
        let directions: Vec<Option<Vec3>> = model
            .axes()
            .iter()
            .map(|a| (a.kind == AxisKind::Prismatic).then_some(a.home_direction))
            .collect();
        let prismatic: Vec<(usize, Vec3)> = directions
            .iter()
            .enumerate()
            .filter_map(|(i, d)| d.map(|d| (i, d)))
            .collect();
        let three = <[(usize, Vec3); 3]>::try_from(prismatic.as_slice()).ok();
        let only_xyz = match directions.as_slice() {
            [Some(a), Some(b), Some(c)] => Some([*a, *b, *c]),
            _ => None,
        };
        LinearAxes {
            directions,
            prismatic,
            three,
            only_xyz,
        }
    }

    /// Number of axes in the chain (linear and rotary).
    pub fn len(&self) -> usize {
        self.directions.len()
    }

    /// Whether the chain has no axes.
    pub fn is_empty(&self) -> bool {
        self.directions.is_empty()
    }

    /// Nominal X, Y, Z (mm) of axis values `q` (chain order): the same sum
    /// as [`MachineModel::linear_xyz`] (`sum q_i * home_direction_i` over
    /// the prismatic axes, in chain order); a missing value counts as 0.
    #[inline(always)]
    pub fn xyz(&self, q: &[f64]) -> Vec3 {
        if let (Some([a, b, c]), [x, y, z, ..]) = (self.only_xyz, q) {
            return Vec3::zeros() + a * *x + b * *y + c * *z;
        }
        let at = |i: usize| q.get(i).copied().unwrap_or(0.0);
        if let Some([(i, a), (j, b), (k, c)]) = self.three {
            return Vec3::zeros() + a * at(i) + b * at(j) + c * at(k);
        }
        self.prismatic
            .iter()
            .fold(Vec3::zeros(), |acc, &(i, d)| acc + d * at(i))
    }

    /// Axis values (chain order) whose linear axes add up to `v`, written
    /// over `out` (one value per axis); rotary axes get zero.
    #[inline(always)]
    pub fn to_axes_into(&self, v: Vec3, out: &mut Vec<f64>) {
        out.resize(self.directions.len(), 0.0);
        if let (Some([a, b, c]), [x, y, z]) = (self.only_xyz, out.as_mut_slice()) {
            (*x, *y, *z) = (a.dot(&v), b.dot(&v), c.dot(&v));
            return;
        }
        for (o, d) in out.iter_mut().zip(&self.directions) {
            *o = d.map_or(0.0, |d| d.dot(&v));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Same values, bit for bit, as the model's own conversion on the
    /// default bridge.
    #[test]
    fn matches_the_model() {
        let model = MachineModel::default_bridge();
        let linear = LinearAxes::new(&model);
        assert_eq!(linear.len(), model.axes().len());
        let q = [123.456, -0.0, 987.125e-3];
        let expected = model.linear_xyz(&q).map(Vec3::from).ok();
        assert_eq!(Some(linear.xyz(&q)), expected);
        let v = Vec3::new(1.5, -2.25, 3.0);
        let mut out = vec![7.0; 5];
        linear.to_axes_into(v, &mut out);
        let by_model: Vec<f64> = model
            .axes()
            .iter()
            .map(|a| a.home_direction.dot(&v))
            .collect();
        assert_eq!(out, by_model);
    }

    /// Both conversions bit for bit against the model's own on a bridge
    /// with a head (five axes: the general path) and on the plain bridge
    /// (three: the one-to-one path), over a seeded sweep of values with
    /// signed zeros.
    #[test]
    fn matches_the_model_with_and_without_head() {
        use crate::machine::builtin::BRIDGE_AB_HEAD_URDF;
        let head = MachineModel::from_urdf_str(BRIDGE_AB_HEAD_URDF, "builtin-head")
            .unwrap_or_else(|e| panic!("builtin head machine: {e}"));
        let mut x: u64 = 0x2545_f491_4f6c_dd1d;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            ((x >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 1e3
        };
        let bits = |w: &[f64]| w.iter().map(|c| c.to_bits()).collect::<Vec<_>>();
        for model in [MachineModel::default_bridge(), head] {
            let linear = LinearAxes::new(&model);
            let n = model.axes().len();
            for case in 0..200 {
                let mut q: Vec<f64> = (0..n).map(|_| next()).collect();
                if case % 5 == 0 {
                    q.iter_mut().for_each(|c| *c = -0.0);
                }
                let expected = model.linear_xyz(&q).map(|c| bits(&c)).ok();
                assert_eq!(Some(bits(linear.xyz(&q).as_slice())), expected, "{q:?}");
                let v = Vec3::new(next(), -0.0, next());
                let mut out = Vec::new();
                linear.to_axes_into(v, &mut out);
                let by_model: Vec<f64> = model
                    .axes()
                    .iter()
                    .map(|a| match a.kind {
                        AxisKind::Prismatic => a.home_direction.dot(&v),
                        AxisKind::Revolute => 0.0,
                    })
                    .collect();
                assert_eq!(bits(&out), bits(&by_model));
            }
        }
    }
}
