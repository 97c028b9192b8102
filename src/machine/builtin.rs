//! Embedded machine descriptions (URDF, metres and radians; see
//! [`super::urdf::MM_PER_M`] for the conversion to mm).
//!
//! Both are bridge CMMs whose chain runs table -> `y` (bridge) -> `x`
//! (carriage on the bridge) -> `z` (ram), so axis values are given in the
//! order `[y, x, z, ...]`; use [`super::MachineModel::axis_index`] to find an
//! axis by name. With every joint origin at zero, the spindle reference point
//! sits at `(x, y, z)` in machine coordinates.

/// The default bridge CMM: X 0-700 mm, Y 0-1000 mm, Z 0-600 mm, 500 mm/s on
/// each axis; the tip link `spindle` is the spindle reference point.
pub const DEFAULT_BRIDGE_URDF: &str = r#"<?xml version="1.0"?>
<!-- cmm default bridge CMM. URDF units: metres, radians, m/s. -->
<robot name="cmm-default-bridge">
  <link name="table"/>
  <link name="bridge"/>
  <link name="carriage"/>
  <link name="spindle"/>
  <joint name="y" type="prismatic">
    <parent link="table"/>
    <child link="bridge"/>
    <axis xyz="0 1 0"/>
    <limit lower="0" upper="1.0" velocity="0.5" effort="0"/>
  </joint>
  <joint name="x" type="prismatic">
    <parent link="bridge"/>
    <child link="carriage"/>
    <axis xyz="1 0 0"/>
    <limit lower="0" upper="0.7" velocity="0.5" effort="0"/>
  </joint>
  <joint name="z" type="prismatic">
    <parent link="carriage"/>
    <child link="spindle"/>
    <axis xyz="0 0 1"/>
    <limit lower="0" upper="0.6" velocity="0.5" effort="0"/>
  </joint>
</robot>
"#;

/// Distance from the spindle reference point down to the B-axis centre of
/// the example probe head, mm.
pub const AB_HEAD_B_OFFSET_MM: f64 = 50.0;
/// Distance from the B-axis centre down to the A-axis (tilt) centre, mm.
pub const AB_HEAD_A_OFFSET_MM: f64 = 30.0;
/// Distance from the A-axis centre to the probe mount, along the head's -z
/// (rotated by A and B), mm.
pub const AB_HEAD_MOUNT_OFFSET_MM: f64 = 20.0;

/// The default bridge with a two-axis probe head below the ram: `b` rotates
/// about the vertical (-180..180 deg), then `a` tilts about the head's x axis
/// (0..105 deg); the tip link `probe_mount` is where the stylus is fixed.
/// Also shipped as `part-programs/machines/bridge-ab-head.urdf`.
pub const BRIDGE_AB_HEAD_URDF: &str = r#"<?xml version="1.0"?>
<!-- cmm bridge CMM with an A/B probe head. URDF units: metres, radians, m/s, rad/s. -->
<robot name="cmm-bridge-ab-head">
  <link name="table"/>
  <link name="bridge"/>
  <link name="carriage"/>
  <link name="spindle"/>
  <link name="head"/>
  <link name="b_body"/>
  <link name="a_body"/>
  <link name="probe_mount"/>
  <joint name="y" type="prismatic">
    <parent link="table"/>
    <child link="bridge"/>
    <axis xyz="0 1 0"/>
    <limit lower="0" upper="1.0" velocity="0.5" effort="0"/>
  </joint>
  <joint name="x" type="prismatic">
    <parent link="bridge"/>
    <child link="carriage"/>
    <axis xyz="1 0 0"/>
    <limit lower="0" upper="0.7" velocity="0.5" effort="0"/>
  </joint>
  <joint name="z" type="prismatic">
    <parent link="carriage"/>
    <child link="spindle"/>
    <axis xyz="0 0 1"/>
    <limit lower="0" upper="0.6" velocity="0.5" effort="0"/>
  </joint>
  <joint name="head_mount" type="fixed">
    <parent link="spindle"/>
    <child link="head"/>
    <origin xyz="0 0 -0.05" rpy="0 0 0"/>
  </joint>
  <joint name="b" type="revolute">
    <parent link="head"/>
    <child link="b_body"/>
    <axis xyz="0 0 1"/>
    <limit lower="-3.14159265358979" upper="3.14159265358979" velocity="1.5" effort="0"/>
  </joint>
  <joint name="a" type="revolute">
    <parent link="b_body"/>
    <child link="a_body"/>
    <origin xyz="0 0 -0.03" rpy="0 0 0"/>
    <axis xyz="1 0 0"/>
    <limit lower="0" upper="1.83259571459405" velocity="1.5" effort="0"/>
  </joint>
  <joint name="stylus_mount" type="fixed">
    <parent link="a_body"/>
    <child link="probe_mount"/>
    <origin xyz="0 0 -0.02" rpy="0 0 0"/>
  </joint>
</robot>
"#;
