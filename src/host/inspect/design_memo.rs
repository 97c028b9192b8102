//! Section designs remembered across the runs of one program: the design
//! points a ball follows on a section curve ([`super::corners::section_design`])
//! depend only on the design data, the curve (part coordinates) and the
//! ball radius, so a batch's variants, whatever their alignment, share
//! them. A remembered design is the one the computation gives (the key
//! holds the ball radius's bits and the curve's place in the program, whose
//! curves are fixed when it is loaded), so reports do not depend on what
//! was remembered.
use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use super::correction::DesignPoint;

/// A curve's design: the feature's name, the curve's index in it and the
/// bits of the ball radius.
type Key = (String, usize, u64);

/// The section designs of one program, shared between threads.
#[derive(Debug, Clone, Default)]
pub struct DesignMemo {
    table: Arc<Mutex<HashMap<Key, Arc<Vec<DesignPoint>>>>>,
}

impl DesignMemo {
    /// The design of curve `curve` of feature `feature` for a ball of
    /// radius `r` (mm): the remembered one, else `make`'s (then
    /// remembered).
    pub fn design(
        &self,
        (feature, curve): (&str, usize),
        r: f64,
        make: impl FnOnce() -> Vec<DesignPoint>,
    ) -> Arc<Vec<DesignPoint>> {
        let key = (feature.to_string(), curve, r.to_bits());
        if let Some(d) = self.table.lock().ok().and_then(|t| t.get(&key).cloned()) {
            return d;
        }
        let made = Arc::new(make());
        if let Ok(mut t) = self.table.lock() {
            t.insert(key, Arc::clone(&made));
        }
        made
    }

    /// Number of designs remembered.
    pub fn len(&self) -> usize {
        self.table.lock().map_or(0, |t| t.len())
    }

    /// Whether nothing is remembered yet.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Point3, Vec3};

    fn point(x: f64) -> DesignPoint {
        DesignPoint {
            point: Point3::new(x, 0.0, 0.0),
            normal: Vec3::z(),
        }
    }

    #[test]
    fn makes_each_design_once_per_curve_and_radius() {
        let memo = DesignMemo::default();
        let mut made = 0;
        for _ in 0..3 {
            let d = memo.design(("a", 0), 1.5, || {
                made += 1;
                vec![point(1.0)]
            });
            assert_eq!(d.len(), 1);
        }
        assert_eq!(made, 1);
        // Another curve, another radius: made anew.
        memo.design(("a", 1), 1.5, || vec![point(2.0)]);
        let other = memo.design(("a", 0), 0.5, || vec![point(3.0), point(4.0)]);
        assert_eq!(other.len(), 2);
        assert_eq!(memo.len(), 3);
    }
}
