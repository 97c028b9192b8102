//! Plane sections (placeholder while written).
