//! Geometry kernel: NURBS curves and surfaces, closest-point projection,
//! plane sections and offsets. f64, millimetres.

mod chord_tree;
pub mod nurbs;
pub mod plane;
pub mod projection;
pub mod section;
pub mod trim;

pub use nurbs::bezier::BezierPatch;
pub use nurbs::curve::NurbsCurve;
pub use nurbs::elevate::ElevateError;
pub use nurbs::insert::InsertError;
pub use nurbs::jet::Jet2;
pub use nurbs::knots::{KnotError, KnotVector};
pub use nurbs::surface::{Curvature, NurbsSurface, SurfaceDerivs};
pub use nurbs::NurbsError;
pub use plane::{Plane, PlaneError};
pub use projection::{
    HullShadows, Projection, ProjectionError, ProjectionIndex, ProjectionOptions,
};
pub use section::{SectionCurve, SectionOptions, SectionPoint};
pub use trim::Trim;
