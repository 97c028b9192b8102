//! URDF validation: every broken description is rejected with the file,
//! the joint (or link) and the reason.
use cmm::machine::{MachineError, MachineModel};

const FILE: &str = "broken-machine.urdf";

/// A prismatic joint `name` from `parent` to `child` with a limit element.
fn prismatic(name: &str, parent: &str, child: &str) -> String {
    format!(
        r#"<joint name="{name}" type="prismatic"><parent link="{parent}"/><child link="{child}"/>
           <axis xyz="1 0 0"/><limit lower="0" upper="0.5" velocity="0.5"/></joint>"#
    )
}

fn robot(links: &[&str], joints: &[String]) -> String {
    let links: String = links
        .iter()
        .map(|l| format!(r#"<link name="{l}"/>"#))
        .collect();
    format!(r#"<robot name="r">{links}{}</robot>"#, joints.concat())
}

fn load(text: &str) -> MachineError {
    let err = MachineModel::from_urdf_str(text, FILE).unwrap_err();
    assert!(err.to_string().contains(FILE), "{err}");
    err
}

/// The message names the file and `needle` (a joint or link).
fn assert_names(err: &MachineError, needle: &str) {
    let msg = err.to_string();
    assert!(msg.contains(&format!("'{needle}'")), "{msg}");
}

#[test]
fn missing_limit_names_the_joint() {
    let joint = r#"<joint name="x" type="prismatic"><parent link="a"/><child link="b"/>
                   <axis xyz="1 0 0"/></joint>"#;
    let err = load(&robot(&["a", "b"], &[joint.to_string()]));
    assert!(
        matches!(&err, MachineError::MissingLimit { joint, kind: "prismatic", .. } if joint == "x")
    );
    assert_names(&err, "x");
}

#[test]
fn missing_limit_on_revolute_joint_too() {
    let joint = r#"<joint name="b" type="revolute"><parent link="a"/><child link="b"/>
                   <axis xyz="0 0 1"/></joint>"#;
    let err = load(&robot(&["a", "b"], &[joint.to_string()]));
    assert!(
        matches!(&err, MachineError::MissingLimit { joint, kind: "revolute", .. } if joint == "b")
    );
}

#[test]
fn lower_not_below_upper_is_rejected_in_mm() {
    let joint =
        prismatic("x", "a", "b").replace(r#"lower="0" upper="0.5""#, r#"lower="0.5" upper="0.2""#);
    let err = load(&robot(&["a", "b"], &[joint]));
    match &err {
        MachineError::LimitRange {
            joint,
            lower,
            upper,
            unit,
            ..
        } => {
            assert_eq!(
                (joint.as_str(), *lower, *upper, *unit),
                ("x", 500.0, 200.0, "mm")
            );
        }
        other => panic!("unexpected {other}"),
    }
    assert_names(&err, "x");
}

#[test]
fn explicit_zero_range_is_rejected() {
    let joint = prismatic("z", "a", "b").replace(r#"upper="0.5""#, r#"upper="0""#);
    let err = load(&robot(&["a", "b"], &[joint]));
    assert!(
        matches!(&err, MachineError::LimitRange { lower, upper, .. } if *lower == 0.0 && *upper == 0.0)
    );
    assert_names(&err, "z");
}

#[test]
fn non_positive_velocity_is_rejected() {
    let joint = prismatic("y", "a", "b").replace(r#"velocity="0.5""#, r#"velocity="0""#);
    let err = load(&robot(&["a", "b"], &[joint]));
    assert!(matches!(&err, MachineError::VelocityLimit { velocity, .. } if *velocity == 0.0));
    assert_names(&err, "y");
}

#[test]
fn unsupported_and_unknown_joint_types_are_named() {
    for kind in ["continuous", "floating", "slider"] {
        let joint = prismatic("q", "a", "b").replace("prismatic", kind);
        let err = load(&robot(&["a", "b"], &[joint]));
        assert!(
            matches!(&err, MachineError::UnsupportedJointType { kind: k, .. } if k == kind),
            "{err}"
        );
        assert_names(&err, "q");
        assert!(err.to_string().contains(kind));
    }
}

#[test]
fn zero_and_non_unit_axes_are_rejected() {
    for axis in ["0 0 0", "0 0 2", "0.5 0.5 0"] {
        let joint = prismatic("x", "a", "b").replace("1 0 0", axis);
        let err = load(&robot(&["a", "b"], &[joint]));
        assert!(matches!(&err, MachineError::BadAxis { .. }), "{err}");
        assert_names(&err, "x");
    }
}

#[test]
fn joint_naming_an_undeclared_link_is_rejected() {
    let err = load(&robot(
        &["a", "b"],
        &[prismatic("x", "a", "b"), prismatic("y", "b", "ghost")],
    ));
    assert!(
        matches!(&err, MachineError::UnknownLink { joint, link, role: "child", .. } if joint == "y" && link == "ghost")
    );
    assert_names(&err, "y");
    assert_names(&err, "ghost");
}

#[test]
fn cycle_through_the_base_names_its_joints() {
    let joints = [
        prismatic("j1", "a", "b"),
        prismatic("j2", "b", "c"),
        prismatic("j3", "c", "a"),
    ];
    let err = load(&robot(&["a", "b", "c"], &joints));
    match &err {
        MachineError::Cycle { joints, .. } => {
            let mut sorted = joints.clone();
            sorted.sort();
            assert_eq!(sorted, ["j1", "j2", "j3"]);
        }
        other => panic!("unexpected {other}"),
    }
}

#[test]
fn cycle_beside_a_valid_chain_is_found() {
    let joints = [
        prismatic("x", "base", "tip"),
        prismatic("l1", "p", "q"),
        prismatic("l2", "q", "p"),
    ];
    let err = load(&robot(&["base", "tip", "p", "q"], &joints));
    assert!(
        matches!(&err, MachineError::Cycle { joints, .. } if joints.len() == 2),
        "{err}"
    );
    assert!(err.to_string().contains("l1") && err.to_string().contains("l2"));
}

#[test]
fn link_with_two_parents_is_rejected() {
    let joints = [prismatic("x", "a", "c"), prismatic("y", "b", "c")];
    let err = load(&robot(&["a", "b", "c"], &joints));
    assert!(
        matches!(&err, MachineError::TwoParents { link, first, second, .. }
        if link == "c" && first == "x" && second == "y")
    );
}

#[test]
fn branching_tree_is_not_a_serial_chain() {
    let joints = [prismatic("x", "a", "b"), prismatic("y", "a", "c")];
    let err = load(&robot(&["a", "b", "c"], &joints));
    assert!(matches!(&err, MachineError::Branch { link, .. } if link == "a"));
    assert_names(&err, "x");
    assert_names(&err, "y");
}

#[test]
fn disconnected_link_is_rejected() {
    let err = load(&robot(&["a", "b", "lonely"], &[prismatic("x", "a", "b")]));
    assert!(
        matches!(&err, MachineError::Disconnected { link, base, .. } if link == "lonely" && base == "a")
    );
}

#[test]
fn chain_without_movable_joint_is_rejected() {
    let joint = r#"<joint name="f" type="fixed"><parent link="a"/><child link="b"/></joint>"#;
    let err = load(&robot(&["a", "b"], &[joint.to_string()]));
    assert!(matches!(err, MachineError::Empty { .. }));
}

#[test]
fn duplicate_joint_names_are_rejected() {
    let joints = [prismatic("x", "a", "b"), prismatic("x", "b", "c")];
    let err = load(&robot(&["a", "b", "c"], &joints));
    assert!(matches!(&err, MachineError::Duplicate { element: "joint", name, .. } if name == "x"));
}

#[test]
fn malformed_xml_and_missing_files_name_the_file() {
    let err = load("<robot name='r'><link name='a'></robot>");
    assert!(matches!(err, MachineError::Xml { .. }), "{err}");
    let err = MachineModel::from_urdf_file("/nonexistent/machine.urdf").unwrap_err();
    assert!(matches!(err, MachineError::Io { .. }));
    assert!(err.to_string().contains("/nonexistent/machine.urdf"));
}

#[test]
fn valid_chain_in_any_file_order_is_accepted() {
    let joints = [
        prismatic("z", "c", "d"),
        prismatic("x", "a", "b"),
        prismatic("y", "b", "c"),
    ];
    let m = MachineModel::from_urdf_str(&robot(&["d", "c", "b", "a"], &joints), FILE).unwrap();
    let names: Vec<&str> = m.axes().iter().map(|a| a.name.as_str()).collect();
    assert_eq!(names, ["x", "y", "z"]);
    assert_eq!((m.base_link(), m.tip_link()), ("a", "d"));
}

#[test]
fn limit_without_velocity_or_with_bad_numbers_names_the_joint() {
    let no_velocity = prismatic("x", "a", "b").replace(r#" velocity="0.5""#, "");
    let bad_number = prismatic("x", "a", "b").replace(r#"upper="0.5""#, r#"upper="half""#);
    for (joint, attribute) in [(no_velocity, "velocity"), (bad_number, "upper")] {
        let err = load(&robot(&["a", "b"], &[joint]));
        assert!(
            matches!(&err, MachineError::LimitAttribute { joint, attribute: a, .. }
            if joint == "x" && *a == attribute),
            "{err}"
        );
        assert_names(&err, "x");
    }
}
