//! Tokenizer and parser of the STEP exchange structure: values, positions
//! and malformed inputs with exact line:column.
use cmm::cad::step::lexer::{Lexer, Pos, Tok};
use cmm::cad::step::parser::Value;
use cmm::cad::{parse_step_str, CadError, ImportOptions};

fn wrap(data: &str) -> String {
    format!("ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION(('x'),'2;1');\nENDSEC;\nDATA;\n{data}ENDSEC;\nEND-ISO-10303-21;\n")
}

fn tokens(text: &str) -> Vec<(Tok, Pos)> {
    let mut lex = Lexer::new(text, "t");
    let mut out = Vec::new();
    loop {
        let (tok, pos) = lex.next_token().expect("lexes");
        if tok == Tok::Eof {
            return out;
        }
        out.push((tok, pos));
    }
}

fn at(line: usize, column: usize) -> Pos {
    Pos { line, column }
}

#[test]
fn tokens_carry_exact_positions() {
    let toks = tokens("#12 = NAME('it''s',\n  .T.,$,*, 1.5E2,-3,\"0F\" /* c\n */ );");
    let expected = vec![
        (Tok::Ref(12), at(1, 1)),
        (Tok::Eq, at(1, 5)),
        (Tok::Keyword("NAME".into()), at(1, 7)),
        (Tok::LParen, at(1, 11)),
        (Tok::Str("it's".into()), at(1, 12)),
        (Tok::Comma, at(1, 19)),
        (Tok::Enum("T".into()), at(2, 3)),
        (Tok::Comma, at(2, 6)),
        (Tok::Dollar, at(2, 7)),
        (Tok::Comma, at(2, 8)),
        (Tok::Star, at(2, 9)),
        (Tok::Comma, at(2, 10)),
        (Tok::Real(150.0), at(2, 12)),
        (Tok::Comma, at(2, 17)),
        (Tok::Int(-3), at(2, 18)),
        (Tok::Comma, at(2, 20)),
        (Tok::Binary("0F".into()), at(2, 21)),
        (Tok::RParen, at(3, 5)),
        (Tok::Semi, at(3, 6)),
    ];
    assert_eq!(toks, expected);
}

#[test]
fn reals_in_all_spellings() {
    let reals: Vec<f64> = tokens("1. -2.5E-3 0.E0 1.E+2 .5")
        .into_iter()
        .map(|(t, _)| match t {
            Tok::Real(r) => r,
            other => panic!("{other:?}"),
        })
        .collect();
    assert_eq!(reals, vec![1.0, -2.5e-3, 0.0, 100.0, 0.5]);
}

#[test]
fn string_encodings_are_decoded() {
    let cases = [
        ("'a\\X2\\00E400F6\\X0\\b'", "a\u{e4}\u{f6}b"),
        ("'\\X\\E4'", "\u{e4}"),
        ("'\\S\\d'", "\u{e4}"),
        ("'back\\\\slash'", "back\\slash"),
        ("'\\X4\\0001F600\\X0\\'", "\u{1F600}"),
        ("'split\nline'", "splitline"),
    ];
    for (src, want) in cases {
        let toks = tokens(src);
        assert_eq!(
            toks.first().map(|t| &t.0),
            Some(&Tok::Str(want.into())),
            "{src}"
        );
    }
}

#[test]
fn simple_complex_and_typed_instances() {
    let text = wrap(
        "#1=CARTESIAN_POINT('',(1.,2.,3.));\n#5=(B(1) A(LENGTH_MEASURE(2.5),(#1,$),.MILLI.));\n",
    );
    let step = parse_step_str(&text).expect("parses");
    let p = step.get(1).expect("#1");
    assert_eq!(p.pos, at(6, 1));
    assert_eq!(p.records[0].name, "CARTESIAN_POINT");
    let c = step.get(5).expect("#5");
    assert!(c.complex);
    let names: Vec<&str> = c.records.iter().map(|r| r.name.as_str()).collect();
    assert_eq!(names, ["B", "A"]);
    assert_eq!(
        c.records[1].params,
        vec![
            Value::Typed("LENGTH_MEASURE".into(), Box::new(Value::Real(2.5))),
            Value::List(vec![Value::Ref(1), Value::Null]),
            Value::Enum("MILLI".into()),
        ]
    );
}

fn syntax_at(err: CadError) -> (usize, usize, String) {
    match err {
        CadError::Syntax {
            line,
            column,
            reason,
            ..
        } => (line, column, reason),
        other => panic!("expected a syntax error, got {other:?}"),
    }
}

#[test]
fn truncated_file_reports_end_position() {
    let text = "ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\n#1=CARTESIAN_POINT('',(1.,2.";
    let (line, column, reason) = syntax_at(parse_step_str(text).expect_err("truncated"));
    assert_eq!((line, column), (5, 29));
    assert!(reason.contains("end of file"), "{reason}");
}

#[test]
fn unterminated_string_points_at_its_quote() {
    let text = wrap("#1=A('abc);\n");
    let (line, column, reason) = syntax_at(parse_step_str(&text).expect_err("bad"));
    assert_eq!((line, column), (6, 6));
    assert!(reason.contains("unterminated string"));
}

#[test]
fn bad_syntax_reports_token_position() {
    let text = wrap("#1=A(1,2);\n#2=B(1 2);\n");
    let (line, column, reason) = syntax_at(parse_step_str(&text).expect_err("bad"));
    assert_eq!((line, column), (7, 8));
    assert!(reason.contains("expected ',' or ')'"), "{reason}");
    let text = wrap("#1=A(1)\n#2=B(2);\n");
    assert_eq!(syntax_at(parse_step_str(&text).expect_err("bad")).0, 7);
    let text = wrap("#1=A(?);\n");
    assert_eq!(syntax_at(parse_step_str(&text).expect_err("bad")).1, 6);
}

#[test]
fn unknown_reference_names_the_referencing_entity() {
    let text = wrap("#1=A(1);\n  #2=B(#1,(#7));\n");
    match parse_step_str(&text).expect_err("unknown") {
        CadError::UnknownReference {
            line,
            column,
            entity,
            target,
            ..
        } => {
            assert_eq!((line, column, entity, target), (7, 3, 2, 7));
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn cyclic_reference_is_an_error_not_a_hang() {
    let text = wrap("#1=A(#2);\n#2=B(#3);\n#3=C((#1));\n#4=D(#1);\n");
    match parse_step_str(&text).expect_err("cycle") {
        CadError::CyclicReference {
            line,
            entity,
            reason,
            ..
        } => {
            assert_eq!((line, entity), (6, 1));
            assert_eq!(reason, "#1 -> #2 -> #3 -> #1");
        }
        other => panic!("{other:?}"),
    }
    let self_ref = wrap("#9=A(#9);\n");
    assert!(matches!(
        parse_step_str(&self_ref),
        Err(CadError::CyclicReference { entity: 9, .. })
    ));
}

#[test]
fn long_reference_chain_does_not_overflow() {
    let data: String = (1..20_000)
        .map(|k| format!("#{k}=A(#{});\n", k + 1))
        .collect::<String>()
        + "#20000=A(1);\n";
    assert!(parse_step_str(&wrap(&data)).is_ok());
}

#[test]
fn deep_nesting_is_rejected() {
    let deep = format!("#1=A({}1{});\n", "(".repeat(500), ")".repeat(500));
    let (line, _, reason) = syntax_at(parse_step_str(&wrap(&deep)).expect_err("deep"));
    assert_eq!(line, 6);
    assert!(reason.contains("nesting"));
}

#[test]
fn duplicate_instance_is_an_error() {
    let (line, column, _) =
        syntax_at(parse_step_str(&wrap("#1=A(1);\n#1=B(2);\n")).expect_err("dup"));
    assert_eq!((line, column), (7, 1));
}

const PLANE_FACE: &str = "#10=CARTESIAN_POINT('',(0.,0.,0.));
#11=DIRECTION('',(0.,0.,1.));
#12=DIRECTION('',(1.,0.,0.));
#13=AXIS2_PLACEMENT_3D('',#10,#11,#12);
#14=PLANE('',#13);
#20=CARTESIAN_POINT('',(0.,0.,0.));
#21=CARTESIAN_POINT('',(1.,0.,0.));
#22=CARTESIAN_POINT('',(0.,1.,0.));
#23=VERTEX_POINT('',#20);
#24=VERTEX_POINT('',#21);
#25=VERTEX_POINT('',#22);
#26=DIRECTION('',(1.,0.,0.));
#27=VECTOR('',#26,1.);
#28=LINE('',#20,#27);
#29=DIRECTION('',(-1.,1.,0.));
#30=VECTOR('',#29,1.);
#31=LINE('',#21,#30);
#32=DIRECTION('',(0.,-1.,0.));
#33=VECTOR('',#32,1.);
#34=LINE('',#22,#33);
#35=EDGE_CURVE('',#23,#24,#28,.T.);
#36=EDGE_CURVE('',#24,#25,#31,.T.);
#37=EDGE_CURVE('',#25,#23,#34,.T.);
#38=ORIENTED_EDGE('',*,*,#35,.T.);
#39=ORIENTED_EDGE('',*,*,#36,.T.);
#40=ORIENTED_EDGE('',*,*,#37,.T.);
#41=EDGE_LOOP('',(#38,#39,#40));
#42=FACE_OUTER_BOUND('',#41,.T.);
#43=ADVANCED_FACE('tri',(#42),#14,.F.);
#44=CLOSED_SHELL('',(#43));
#45=MANIFOLD_SOLID_BREP('',#44);
";

const INCH_CONTEXT: &str = "#50=(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(.MILLI.,.METRE.));
#51=LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE(25.4),#50);
#52=(CONVERSION_BASED_UNIT('INCH',#51)LENGTH_UNIT()NAMED_UNIT(*));
#53=(GEOMETRIC_REPRESENTATION_CONTEXT(3)GLOBAL_UNIT_ASSIGNED_CONTEXT((#52))REPRESENTATION_CONTEXT('',''));
#54=ADVANCED_BREP_SHAPE_REPRESENTATION('',(#45),#53);
";

fn import_text(text: &str) -> Result<cmm::cad::Import, CadError> {
    cmm::cad::step::import_step(text, "mem.step", "mem", &ImportOptions::default())
}

#[test]
fn missing_units_is_an_error() {
    match import_text(&wrap(PLANE_FACE)).expect_err("no units") {
        CadError::MissingUnits {
            line, column, file, ..
        } => {
            assert_eq!((file.as_str(), line, column), ("mem.step", 5, 1));
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn inch_plane_face_converts_with_trim_and_orientation() {
    let imp = import_text(&wrap(&format!("{PLANE_FACE}{INCH_CONTEXT}"))).expect("imports");
    assert_eq!(imp.workpiece.surfaces.len(), 1);
    let s = &imp.workpiece.surfaces[0];
    assert_eq!(s.name, "tri");
    assert!(s.reversed, "same_sense .F. flips the normal");
    let trim = s.trim.as_ref().expect("trim");
    let want = [[0.0, 0.0], [25.4, 0.0], [0.0, 25.4]];
    assert_eq!(trim.outer.len(), 3);
    for (got, want) in trim.outer.iter().zip(want) {
        assert!(
            (got[0] - want[0]).abs() < 1e-12 && (got[1] - want[1]).abs() < 1e-12,
            "{got:?}"
        );
    }
    assert!(
        s.knots_u[0] < 0.0 && s.knots_u[3] > 25.4,
        "plane covers the face with a margin"
    );
}

#[test]
fn file_without_faces_is_an_error() {
    let text = wrap(&format!("{INCH_CONTEXT}#45=A(1);\n"));
    assert!(matches!(
        import_text(&text),
        Err(CadError::NoFaces { line: 5, .. })
    ));
}

#[test]
fn import_dispatches_on_extension() {
    match cmm::cad::import("part.dxf").expect_err("dxf") {
        CadError::UnsupportedType { file, reason, .. } => {
            assert_eq!(file, "part.dxf");
            assert!(reason.contains("dxf"));
        }
        other => panic!("{other:?}"),
    }
    assert!(matches!(
        cmm::cad::import("/nonexistent/part.STP"),
        Err(CadError::Io { .. })
    ));
    assert!(matches!(
        cmm::cad::import("/nonexistent/part.IGS"),
        Err(CadError::Io { .. })
    ));
}

#[test]
fn error_messages_name_file_line_and_column() {
    let err = cmm::cad::step::parse_step(&wrap("#1=A(1);\n#2=B(#9);\n"), "part.step")
        .expect_err("unknown");
    assert_eq!(
        err.to_string(),
        "part.step:7:1: #2 references #9, which is not defined"
    );
}

#[test]
fn si_metre_and_degree_units() {
    let context = "#50=(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT($,.METRE.));
#51=(NAMED_UNIT(*)PLANE_ANGLE_UNIT()SI_UNIT($,.RADIAN.));
#52=PLANE_ANGLE_MEASURE_WITH_UNIT(PLANE_ANGLE_MEASURE(0.0174532925199433),#51);
#53=(CONVERSION_BASED_UNIT('DEGREE',#52)NAMED_UNIT(*)PLANE_ANGLE_UNIT());
#54=(GEOMETRIC_REPRESENTATION_CONTEXT(3)GLOBAL_UNIT_ASSIGNED_CONTEXT((#50,#53))REPRESENTATION_CONTEXT('',''));
#55=ADVANCED_BREP_SHAPE_REPRESENTATION('',(#45),#54);
";
    let step = parse_step_str(&wrap(&format!("{PLANE_FACE}{context}"))).expect("parses");
    let units = cmm::cad::step::units::find_units(&step, "mem").expect("units");
    assert_eq!(units.length_mm, 1000.0);
    assert!((units.angle_rad - std::f64::consts::PI / 180.0).abs() < 1e-15);
    let imp = import_text(&wrap(&format!("{PLANE_FACE}{context}"))).expect("imports");
    let far = imp.workpiece.surfaces[0].trim.as_ref().map(|t| t.outer[1]);
    assert_eq!(far, Some([1000.0, 0.0]));
}
