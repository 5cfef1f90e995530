//! Plain-text records as users write them: format detection, refusals
//! that say what to do, units named in column headers, the 5 g
//! plausibility limit and what a loaded record reports (format, units,
//! unit factor and user scale apart, the file's own PGA). Small inline
//! files only.

use quakejoint_motion::{detect_format, load_record_from_str, Format, LoadedRecord, RecordError, RecordSpec, Units, G};

fn spec(file: &str, units: Option<Units>, dt: Option<f64>, column: Option<usize>) -> RecordSpec {
    let mut s = RecordSpec::new(file);
    (s.units, s.dt, s.column) = (units, dt, column);
    s
}

fn load(s: &RecordSpec, text: &str) -> Result<LoadedRecord, RecordError> {
    load_record_from_str(s, text)
}

fn err(s: &RecordSpec, text: &str) -> String {
    load(s, text).unwrap_err().to_string()
}

const GAL: Option<Units> = Some(Units::CentimetersPerSecond2);
const MS2: Option<Units> = Some(Units::MetersPerSecond2);
const UG: Option<Units> = Some(Units::G);

#[test]
fn auto_detects_content_but_keeps_the_at2_extension_rule() {
    let esm = "EVENT_NAME: X\nSAMPLING_INTERVAL_S: 0.01\nUNITS: cm/s^2\nDATA_TYPE: ACCELERATION\n0\n1\n";
    for (file, dt, text, want) in [
        ("a.ASC", None, esm, Format::Esm),
        ("a.AT2", None, esm, Format::At2),
        ("a.txt", None, "Origin Time  x\n", Format::Knet),
        ("a.V2", None, "Corrected acceleration  (Format v01.20 with 13 text lines)\n", Format::Cosmos),
        ("a.txt", Some(0.01), "0.1\n", Format::OneColumn),
        ("a.csv", None, "t,a\n0,0.1\n", Format::TwoColumn),
    ] {
        assert_eq!(detect_format(&spec(file, None, dt, None), text), want, "{file}: {text:?}");
    }
    assert_eq!(load(&RecordSpec::new("a.ASC"), esm).unwrap().format, Format::Esm);
    assert_eq!(load(&spec("a.txt", UG, Some(0.01), None), "0\n0.1\n").unwrap().format, Format::OneColumn);
    assert_eq!(load(&spec("a.csv", UG, None, None), "0 0\n0.01 0.1\n").unwrap().format, Format::TwoColumn);
}

#[test]
fn a_header_of_an_unknown_format_is_not_numeric_data() {
    let s = spec("x.txt", UG, Some(0.01), None);
    let m = err(&s, "Station: XYZ\nLat.: 37.0\n0.1\n0.2\n");
    assert!(m.starts_with("x.txt:2: `Lat.: 37.0` is not numeric data (line 1 was taken as the column header"), "{m}");
    for part in [
        "Formats read: PEER NGA `.AT2`; ESM ASCII",
        "K-NET/KiK-net ASCII",
        "COSMOS V1/V2",
        "plain numeric text or CSV",
        "remove the header and read the values with `format = \"sequence\"`, `dt` and `units`",
        "two-column CSV",
    ] {
        assert!(m.contains(part), "{part}: {m}");
    }
    // a K-NET header cut before `Origin Time`: the line quoted, shortened
    let m = err(&s, "Lat.              37.040\nLong.             -121.880\n0.1\n");
    assert!(m.starts_with("x.txt:1: `Lat.              37.040` is not numeric data."), "{m}");
    let long = format!("Comment {}\n0.1\n", "x".repeat(1000));
    let m = err(&spec("x.txt", UG, None, None), &format!("t a\n{long}"));
    assert!(m.contains("more bytes)` is not numeric data") && m.len() < 1500, "{m}");
    // a known format read with the wrong `format`, a PEER file renamed
    let mut two = spec("x.txt", GAL, None, None);
    two.format = Format::TwoColumn;
    let m = err(&two, "Corrected acceleration  (Format v01.20 with 13 text lines)\nLoma Prieta\n");
    assert!(
        m.contains(
            "The file looks like COSMOS V1/V2: read it with `format = \"auto\"` (`--format auto`, the default) or \
                    `\"cosmos\"` (`--format cosmos`)"
        ),
        "{m}"
    );
    // a CSMIP file read as a sequence: not advised to read it as a sequence
    let mut seq = spec("x.v1", UG, Some(0.01), None);
    seq.format = Format::Sequence;
    let m = err(&seq, "Uncorrected Accelerogram Data             Processed: 07/06/19\nRcrd of Fri Jul  5, 2019\n");
    assert!(m.contains("The file looks like CSMIP/DMG Volume 1/2") && m.contains("`--format csmip`"), "{m}");
    assert!(!m.contains("format = \"sequence\"") && m.contains("A sequence holds numbers only"), "{m}");
    assert!(m.lines().all(|l| l.len() <= 500), "every line of a message is short: {m}");
    let m = err(&spec("r.txt", UG, None, None), "PEER NGA\nLoma Prieta, 1989\nACCELERATION\nNPTS= 2, DT= .01\n1 2\n");
    assert!(m.contains("looks like a PEER NGA AT2 file: name it `.AT2` or set `format = \"at2\"`"), "{m}");
    // ESM keys without their first line
    let m = err(&spec("e.txt", GAL, Some(0.01), None), "USER4: \nUSER5: \n1\n");
    assert!(m.contains("look like an ESM header, but an ESM file starts with `EVENT_NAME:`"), "{m}");
}

#[test]
fn one_value_per_line_without_dt() {
    let m = err(&spec("acc_g.txt", UG, None, None), "1.7655510e-03\n1.7657510e-03\n");
    assert!(m.starts_with("acc_g.txt:1: the line has 1 field but a two-column file"), "{m}");
    assert!(m.contains("a file with one value per line needs the time step `dt` [s] (and `units`)"), "{m}");
}

#[test]
fn several_values_per_line() {
    // read as one-column: say `sequence` for samples, `column` for quantities
    let body = "     3965     3965     3966     3967\n     3974     3976     3979     3982\n";
    let m = err(&spec("knet_data.txt", GAL, Some(0.01), None), body);
    assert!(m.starts_with("knet_data.txt:1: the line has 4 fields; a one-column file holds one value per line"), "{m}");
    assert!(
        m.contains("successive samples") && m.contains("`format = \"sequence\"`") && m.contains("set `column`"),
        "{m}"
    );
    // read as two-column (no dt): column 1 is no time axis
    let m = err(&spec("knet_data.txt", GAL, None, None), "1 9 9\n3 9 9\n2 9 9\n");
    assert!(m.contains("the time column is not uniform") && m.contains("`format = \"sequence\"`"), "{m}");
    // `column` on a sequence wrapped k per line (the last line shorter)
    let m = err(&spec("knet_data.txt", GAL, Some(0.01), Some(1)), "1 2 3\n4 5 6\n7 8\n");
    assert!(
        m.starts_with("knet_data.txt: field `column`: line 3 (the last) holds 2 values where the others hold 3"),
        "{m}"
    );
    assert!(m.contains("would read one sample in 3") && m.contains("`format = \"sequence\"`"), "{m}");
}

#[test]
fn column_and_dt_on_a_file_with_a_time_column() {
    let text = "time,acc_cm_s2\n0.000,1.0\n0.005,2.0\n0.010,-1.0\n0.015,0.5\n";
    let m = err(&spec("acc.csv", GAL, Some(0.01), Some(2)), text);
    assert!(
        m.starts_with("acc.csv: field `dt`: column 1 is a time axis with a step of 0.005 s but `dt = 0.01` s"),
        "{m}"
    );
    assert!(m.contains("drop `dt`"), "{m}");
    // the same step is accepted; column 1 picked is refused
    assert_eq!(load(&spec("acc.csv", GAL, Some(0.005), Some(2)), text).unwrap().record.dt, 0.005);
    let m = err(&spec("acc.csv", GAL, Some(0.005), Some(1)), text);
    assert!(m.starts_with("acc.csv: field `column`: column 1 is a time axis"), "{m}");
    // a multi-column table whose column 1 is not a time axis is read
    let rec = load(&spec("t.txt", GAL, Some(0.01), Some(2)), "5 1.0\n7 2.0\n6 3.0\n").unwrap().record;
    assert_eq!(rec.acceleration, vec![0.01, 0.02, 0.03]);
}

#[test]
fn decimal_commas_are_refused() {
    for (file, text, token) in [
        ("acc_eu.csv", "Zeit;Beschleunigung [m/s2]\n0,000;0,01731414\n0,005;0,01731610\n", "0,000"),
        ("acc_eu_tab.txt", "Zeit\tBeschleunigung\n0,000\t0,01731414\n0,005\t0,01731610\n", "0,000"),
        ("acc_eu_space.txt", "0,000 0,01731414\n0,005 0,01731610\n", "0,000"),
        ("acc_eu_comma.csv", "t,a\n0,000,0,01731414\n0,005,0,01731610\n", "0,000"),
        ("one.txt", "acc\n0,0173\n", "0,0173"),
    ] {
        let m = err(&spec(file, MS2, None, None), text);
        let want = format!("decimal commas are not read: convert `{token}` to `{}`", token.replace(',', "."));
        assert!(m.starts_with(file) && m.contains(&want), "{file}: {m}");
    }
    // commas that split a line inconsistently
    let m = err(&spec("c.csv", MS2, None, None), "0,1.5\n0.01,2,5\n");
    assert!(m.starts_with("c.csv:2: the line has 3 fields where line 1 has 2") && m.contains("decimal commas"), "{m}");
    // semicolons and points are fine
    let rec = load(&spec("ok.csv", MS2, None, None), "t;a\n0.000;0.5\n0.005;-0.5\n").unwrap().record;
    assert_eq!((rec.dt, rec.acceleration.clone()), (0.005, vec![0.5, -0.5]));
}

#[test]
fn units_named_in_a_column_header() {
    let ms2 = "time,acc_m_s2\n0.000,0.0\n0.005,4.7345\n0.010,-1.0\n";
    // `units` that disagree with the label: both named
    let m = err(&spec("acc_ms2.csv", UG, None, None), ms2);
    assert!(
        m.starts_with(
            "acc_ms2.csv: field `units`: the column header `acc_m_s2` says m/s2 but the config says `units = \"g\"`"
        ),
        "{m}"
    );
    // no `units`: the label's suggested, never used on its own
    let m = err(&spec("acc_ms2.csv", None, None, None), ms2);
    assert!(m.contains("the column header `acc_m_s2` suggests `units = \"m/s2\"`; confirm it"), "{m}");
    assert_eq!(load(&spec("acc_ms2.csv", MS2, None, None), ms2).unwrap().record.acceleration[1], 4.7345);
    for (file, text, label, units) in [
        ("a.txt", "time   acc [g]\n0 0\n0.01 0.1\n", "acc [g]", "g"),
        ("b.csv", "Zeit;Beschleunigung [m/s2]\n0;0\n0.01;0.1\n", "Beschleunigung [m/s2]", "m/s2"),
        ("c.csv", "t, accel (cm/s^2)\n0,0\n0.01,0.1\n", "accel (cm/s^2)", "cm/s2"),
        ("d.csv", "time,acc_g\n0,0\n0.01,0.1\n", "acc_g", "g"),
        ("e.txt", "acc_g\n0\n0.1\n", "acc_g", "g"),
    ] {
        let dt = if file == "e.txt" { Some(0.01) } else { None };
        let m = err(&spec(file, None, dt, None), text);
        assert!(m.contains(&format!("the column header `{label}` suggests `units = \"{units}\"`")), "{file}: {m}");
        let other = if units == "g" { GAL } else { UG };
        let m = err(&spec(file, other, dt, None), text);
        assert!(m.contains(&format!("the column header `{label}` says {units} but the config says")), "{file}: {m}");
    }
    // a label naming no unit, or `a_g` (a symbol), needs `units` as before
    for text in ["t,acc\n0,0\n0.01,0.1\n", "t,a_g\n0,0\n0.01,0.1\n"] {
        assert!(err(&spec("f.csv", None, None, None), text).contains("a text record cannot say its units"));
        assert!(load(&spec("f.csv", GAL, None, None), text).is_ok());
    }
    // an unknown bracketed unit warns when `units` is given
    let w = load(&spec("f.csv", MS2, None, None), "t,acc [mm/s2]\n0,0\n0.01,0.1\n").unwrap().warnings;
    assert!(w.iter().any(|w| w.contains("`mm/s2` are not recognised")), "{w:?}");
    // a time column in milliseconds
    let m = err(&spec("ms.csv", UG, None, None), "time_ms,acc_g\n0,0\n5,0.1\n");
    assert!(m.starts_with("ms.csv:1: the time column's header `time_ms` says milliseconds"), "{m}");
}

#[test]
fn nothing_beyond_5_g() {
    // m/s² read as g is refused as read, even with a target PGA that would
    // scale it down to a plausible one
    let text = "t,acc\n0,0\n0.01,9.8\n0.02,-3\n";
    let m = err(&spec("ms2.csv", UG, None, None), text);
    assert!(m.starts_with("record `ms2.csv`: sample 1 (t = 0.01 s) is 9.8 g in the file, beyond 5 g"), "{m}");
    assert!(m.contains("no recorded ground motion is that strong") && m.contains("check `units`"), "{m}");
    let mut s = spec("ms2.csv", UG, None, None);
    s.target_pga_g = Some(0.3);
    assert!(err(&s, text).contains("beyond 5 g"));
    // cm/s² read as m/s²: the g value named
    let m = err(&spec("gal.csv", MS2, None, None), "0 0\n0.01 473.45\n");
    assert!(m.contains("is 473.45 m/s2 in the file (48.278 g), beyond 5 g"), "{m}");
    // the scaled record too; and target_pga_g at most 5 g
    let mut s = spec("a.csv", UG, None, None);
    s.scale = 2.0;
    assert!(err(&s, "0 0\n0.01 3\n").contains("beyond 5 g"));
    s.scale = 1.0;
    s.target_pga_g = Some(5.1);
    let m = err(&s, "0 0\n0.01 0.3\n");
    assert!(m.starts_with("a.csv: field `target_pga_g`: target_pga_g = 5.1 g must be above 0 and at most 5 g"), "{m}");
    s.target_pga_g = Some(5.0);
    assert!((load(&s, "0 0\n0.01 0.3\n").unwrap().record.pga() - 5.0 * G).abs() < 1e-12);
}

#[test]
fn the_record_reports_what_a_user_must_see() {
    let mut s = spec("r.csv", GAL, None, None);
    s.scale = -2.0;
    let loaded = load(&s, "t,acc\n0,0\n0.01,300\n0.02,-100\n").unwrap();
    let rec = &loaded.record;
    assert_eq!(loaded.format, Format::TwoColumn);
    assert_eq!(
        (rec.units, rec.unit_factor(), rec.user_scale, rec.scale),
        (Units::CentimetersPerSecond2, 0.01, -2.0, -0.02)
    );
    assert_eq!(rec.file_pga, 300.0, "in the file's units, before scaling");
    assert!((rec.pga() - 6.0).abs() < 1e-12);
    // with a target PGA the user factor is the one that reaches it
    let mut s = spec("r.csv", GAL, None, None);
    s.target_pga_g = Some(0.3);
    let rec = load(&s, "t,acc\n0,0\n0.01,300\n0.02,-100\n").unwrap().record;
    assert!((rec.user_scale - 0.3 * G / 3.0).abs() < 1e-15);
    assert!((rec.scale - rec.unit_factor() * rec.user_scale).abs() < 1e-15);
    assert_eq!(rec.file_pga, 300.0);
    // a record built in memory
    let rec = quakejoint_motion::Record::new("m", 0.01, vec![0.0, -2.0, 1.0]).unwrap();
    assert_eq!((rec.user_scale, rec.unit_factor(), rec.file_pga), (1.0, 1.0, 2.0));
}
