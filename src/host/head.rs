//! The host's nominal model of a probe head, from the URDF it was given.
//!
//! With every linear axis at zero, the URDF chain's tip pose `M(angles)` is
//! the probe mount relative to the spindle reference point `B`: joint
//! origins (head offsets) and rotations about the nominal joint axes. A
//! stylus `s` (mm, in the mount's frame) then has the probe vector
//! `P(angles) = M(angles) * s`. The host knows only this nominal model;
//! the true head (world side) differs by assembly errors, which is why every
//! orientation is checked on the reference sphere.
use crate::machine::MachineModel;
use crate::math::{Iso3, Vec3};

/// Why a head model or an orientation was rejected.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum HeadModelError {
    /// The machine has no revolute joint.
    #[error("machine '{machine}' has no probe head (no revolute joint)")]
    NoHead {
        /// Machine (robot) name.
        machine: String,
    },
    /// A named head axis is not a revolute joint of the machine.
    #[error("head axis '{name}' is not a revolute joint of machine '{machine}' (revolute joints: {known})")]
    UnknownAxis {
        /// The name asked for.
        name: String,
        /// Machine name.
        machine: String,
        /// The revolute joints there are, comma separated.
        known: String,
    },
    /// `--head-axes` must name every revolute joint once.
    #[error(
        "{named} head axes named, machine '{machine}' has {revolute} revolute joints ({known})"
    )]
    Unnamed {
        /// Axes named.
        named: usize,
        /// Revolute joints of the machine.
        revolute: usize,
        /// Machine name.
        machine: String,
        /// The revolute joints there are, comma separated.
        known: String,
    },
    /// The orientation has the wrong number of angles.
    #[error("orientation {orientation}: {found} angles given, the head has {expected} axes")]
    Count {
        /// Index of the orientation (1-based, as the user lists them).
        orientation: usize,
        /// Head axes.
        expected: usize,
        /// Angles given.
        found: usize,
    },
    /// An angle outside the joint's travel.
    #[error("orientation {orientation}: axis '{axis}' at {angle_deg} deg is outside its travel {lower_deg:.3}..{upper_deg:.3} deg")]
    Travel {
        /// Index of the orientation (1-based).
        orientation: usize,
        /// Axis name.
        axis: String,
        /// The angle, deg.
        angle_deg: f64,
        /// Lowest angle, deg.
        lower_deg: f64,
        /// Highest angle, deg.
        upper_deg: f64,
    },
}

/// A head orientation checked against the model: angles in the user's axis
/// order (deg) and the full axis vector at zero linear positions.
#[derive(Debug, Clone, PartialEq)]
pub struct Orientation {
    /// Angles as given, deg, in the order of [`HeadModel::axis_names`].
    pub angles_deg: Vec<f64>,
    /// Angles of the head axes in the machine's chain order, rad (what
    /// [`crate::seam::Cmm::index_head`] takes).
    pub chain_angles_rad: Vec<f64>,
    q: Vec<f64>,
}

impl Orientation {
    /// Every axis value (chain order; linear axes at 0 mm, head axes in rad).
    pub fn axis_values(&self) -> &[f64] {
        &self.q
    }
}

/// The nominal head: the machine model and which axes are the head's.
#[derive(Debug, Clone)]
pub struct HeadModel {
    model: MachineModel,
    /// Indices in `q` of the head axes, in the user's order.
    axes: Vec<usize>,
}

impl HeadModel {
    /// The head of `model` with its axes named in `names` (the order in which
    /// orientations list their angles); every revolute joint must be named.
    pub fn new(model: MachineModel, names: &[String]) -> Result<HeadModel, HeadModelError> {
        let revolute = model.revolute_axes();
        let machine = model.name().to_string();
        if revolute.is_empty() {
            return Err(HeadModelError::NoHead { machine });
        }
        let known: Vec<&str> = revolute
            .iter()
            .filter_map(|&i| model.axes().get(i).map(|a| a.name.as_str()))
            .collect();
        let mut axes = Vec::new();
        for name in names {
            match model.axis_index(name).filter(|i| revolute.contains(i)) {
                Some(i) if !axes.contains(&i) => axes.push(i),
                _ => {
                    let (name, known) = (name.clone(), known.join(", "));
                    return Err(HeadModelError::UnknownAxis {
                        name,
                        machine,
                        known,
                    });
                }
            }
        }
        if axes.len() != revolute.len() {
            return Err(HeadModelError::Unnamed {
                named: axes.len(),
                revolute: revolute.len(),
                machine,
                known: known.join(", "),
            });
        }
        Ok(HeadModel { model, axes })
    }

    /// Head axis names in the order orientations list their angles.
    pub fn axis_names(&self) -> Vec<String> {
        let axes = self.model.axes();
        let names = self.axes.iter().filter_map(|&i| axes.get(i));
        names.map(|a| a.name.clone()).collect()
    }

    /// Checks orientation number `index` (1-based, for messages).
    pub fn orientation(
        &self,
        index: usize,
        angles_deg: &[f64],
    ) -> Result<Orientation, HeadModelError> {
        if angles_deg.len() != self.axes.len() {
            return Err(HeadModelError::Count {
                orientation: index,
                expected: self.axes.len(),
                found: angles_deg.len(),
            });
        }
        let mut q = vec![0.0; self.model.axes().len()];
        for (&i, &deg) in self.axes.iter().zip(angles_deg) {
            let Some(axis) = self.model.axes().get(i) else {
                continue;
            };
            let rad = deg.to_radians();
            if !(rad.is_finite() && axis.limits.contains(rad)) {
                return Err(HeadModelError::Travel {
                    orientation: index,
                    axis: axis.name.clone(),
                    angle_deg: deg,
                    lower_deg: axis.limits.lower.to_degrees(),
                    upper_deg: axis.limits.upper.to_degrees(),
                });
            }
            if let Some(slot) = q.get_mut(i) {
                *slot = rad;
            }
        }
        let revolute = self.model.revolute_axes();
        let chain_angles_rad = revolute.iter().filter_map(|&i| q.get(i).copied()).collect();
        Ok(Orientation {
            angles_deg: angles_deg.to_vec(),
            chain_angles_rad,
            q,
        })
    }

    /// Nominal probe mount relative to the spindle reference point.
    pub fn mount(&self, o: &Orientation) -> Iso3 {
        self.model.pose(&o.q).unwrap_or_else(|_| Iso3::identity())
    }

    /// Nominal probe vector of stylus `stylus` (mount frame, mm).
    pub fn probe_vector(&self, o: &Orientation, stylus: &Vec3) -> Vec3 {
        (self.mount(o) * crate::math::Point3::from(*stylus)).coords
    }

    /// The stylus (mount frame) that has probe vector `p` at `o`.
    pub fn stylus(&self, o: &Orientation, p: &Vec3) -> Vec3 {
        let mount = self.mount(o);
        mount
            .inverse_transform_point(&crate::math::Point3::from(*p))
            .coords
    }
}
