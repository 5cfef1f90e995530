//! Test 6: the file formats and their quirks, units, scaling.
//!
//! Expected values are written out by hand (or taken from the file's own
//! text), never from an earlier run of the parser.

mod common;

use common::ground_motions;
use quakejoint_motion::{load_record, load_record_from_str, parse_at2, Format, RecordSpec, Units, G};

const H123: &str =
    "PEER NGA STRONG MOTION DATABASE RECORD\nTest, 1/1/2000, Station, 0\nACCELERATION TIME SERIES IN UNITS OF G\n";
const VALUES: [f64; 7] = [-0.8338791e-3, 0.1e-2, -0.25, 0.5, 1.0, -0.75e-1, 0.125];
const BODY: &str =
    "  -.8338791E-03   .1000000E-02  -.2500000E+00   .5000000E+00   .1000000E+01\n  -.7500000E-01   .1250000E+00\n";

fn crlf(s: &str) -> String {
    s.replace('\n', "\r\n")
}

#[test]
fn at2_header_spellings_and_line_ends() {
    let lines4 = [
        "NPTS=      7, DT=   .0050 SEC,                                             ",
        "NPTS=      7, DT=   .0050 SEC                                              ",
        "NPTS= 7 DT= 0.005",
        "      7   .0050    NPTS, DT",
    ];
    for l4 in lines4 {
        let lf = format!("{H123}{l4}\n{BODY}");
        for text in [lf.clone(), crlf(&lf), format!("{}\r\n\r\n", crlf(&lf).trim_end())] {
            let r = parse_at2(&text, "t.AT2").unwrap_or_else(|e| panic!("{l4}: {e}"));
            assert_eq!(r.dt, 0.005, "{l4}");
            assert_eq!(r.values, VALUES, "{l4}");
            assert_eq!(r.header.len(), 4);
            assert_eq!(r.header[3], l4.trim_end(), "header kept without the line end");
            assert_eq!(r.header_units, quakejoint_motion::HeaderUnits::Stated(Units::G));
        }
    }
}

#[test]
fn real_file_with_lf_reads_the_same_as_crlf() {
    let path = ground_motions().join("RSN1690_NORTH151_SYL090-hor1.AT2");
    let text = std::fs::read_to_string(path).unwrap();
    assert!(text.contains(", DT=   .0200 SEC   ") && !text.contains("SEC,"), "this file has no comma after SEC");
    let crlf_rec = parse_at2(&text, "a").unwrap();
    let lf_rec = parse_at2(&text.replace("\r\n", "\n"), "a").unwrap();
    assert_eq!(crlf_rec, lf_rec);
    assert_eq!((crlf_rec.values.len(), crlf_rec.dt), (1000, 0.02));
    // first and last values as written in the file
    assert_eq!(crlf_rec.values[0], -0.6867131e-4);
    let last_line = text.trim_end().lines().last().unwrap();
    let last: f64 = last_line.split_whitespace().last().unwrap().parse().unwrap();
    assert_eq!(*crlf_rec.values.last().unwrap(), last);
}

#[test]
fn two_column_csv_and_whitespace() {
    let want = [0.1, -0.2, 0.3, 0.0];
    let texts = [
        "time,acc\n0.0,0.1\n0.02,-0.2\n0.04,0.3\n0.06,0\n",
        "time;acc\r\n0.0;0.1\r\n0.02;-0.2\r\n0.04;0.3\r\n0.06;0\r\n",
        "# comment line\n  0.00   0.1\n\t0.02\t-0.2\n 0.04 .3\n\n0.06  0.0E+00\n",
        "0.0, 0.1,\n0.02, -0.2,\n0.04, 0.3,\n0.06, 0,\n",
    ];
    for text in texts {
        let mut spec = RecordSpec::new("r.csv");
        spec.units = Some(Units::MetersPerSecond2);
        let rec = load_record_from_str(&spec, text).unwrap_or_else(|e| panic!("{text:?}: {e}")).record;
        assert_eq!(rec.dt, 0.02);
        assert_eq!(rec.acceleration, want, "{text:?}");
        assert_eq!(rec.name, "r");
    }
    // acceleration in column 3 of a multi-column file; a time column not starting at 0
    let mut spec = RecordSpec::new("multi.txt");
    spec.column = Some(3);
    spec.units = Some(Units::MetersPerSecond2);
    let loaded = load_record_from_str(&spec, "10.0 9 1.5 7\n10.5 9 2.5 7\n11.0 9 -1.0 7\n").unwrap();
    assert_eq!((loaded.record.dt, loaded.record.acceleration.clone()), (0.5, vec![1.5, 2.5, -1.0]));
    assert!(loaded.warnings.iter().any(|w| w.contains("starts at t = 10")), "{:?}", loaded.warnings);
}

#[test]
fn one_column_with_dt() {
    let mut spec = RecordSpec::new("one.txt");
    spec.dt = Some(0.01);
    spec.units = Some(Units::MetersPerSecond2);
    assert_eq!(spec.resolved_format(), Format::OneColumn);
    let rec = load_record_from_str(&spec, "acc\n0.0\n1.5D-01\n-.25\n\n0.5\n").unwrap().record;
    assert_eq!((rec.dt, rec.acceleration.clone()), (0.01, vec![0.0, 0.15, -0.25, 0.5]));
    assert!((rec.duration() - 0.03).abs() < 1e-15);
    // one column picked out of several
    spec.column = Some(2);
    let rec = load_record_from_str(&spec, "9 0.0 8\n9 0.5 8\n").unwrap().record;
    assert_eq!(rec.acceleration, vec![0.0, 0.5]);
}

#[test]
fn units_conversion() {
    let text = "0 0\n0.01 1\n0.02 -2\n";
    for (units, factor) in [(Units::G, 9.80665), (Units::MetersPerSecond2, 1.0), (Units::CentimetersPerSecond2, 0.01)] {
        let mut spec = RecordSpec::new("u.txt");
        spec.units = Some(units);
        let rec = load_record_from_str(&spec, text).unwrap().record;
        assert_eq!(rec.scale, factor);
        assert_eq!(rec.units, units);
        assert_eq!(rec.acceleration, vec![0.0, factor, -2.0 * factor], "{units:?}");
    }
    // a text file cannot say its units: they are never guessed
    let err = load_record_from_str(&RecordSpec::new("u.txt"), text).unwrap_err().to_string();
    assert!(err.starts_with("u.txt: field `units`: a text record cannot say its units"), "{err}");
    assert_eq!(G, 9.80665);
    // units named in TOML
    for (name, units) in [("g", Units::G), ("m/s2", Units::MetersPerSecond2), ("cm/s2", Units::CentimetersPerSecond2)] {
        let spec: RecordSpec = toml::from_str(&format!("file = \"u.txt\"\nunits = \"{name}\"\n")).unwrap();
        assert_eq!(spec.units, Some(units));
    }
    // an AT2 file read with units other than its header's: refused, naming the field
    let mut spec = RecordSpec::new("x.at2");
    spec.units = Some(Units::CentimetersPerSecond2);
    let text = format!("{H123}NPTS= 2, DT= .01\n0 1\n");
    let err = load_record_from_str(&spec, &text).unwrap_err().to_string();
    assert!(err.starts_with("x.at2: field `units`") && err.contains("header says units of g"), "{err}");
    // the header's own units given explicitly are fine
    spec.units = Some(Units::G);
    assert!(load_record_from_str(&spec, &text).unwrap().warnings.is_empty());
}

#[test]
fn scale_and_target_pga() {
    let text = "0 0\n0.01 0.5\n0.02 -0.25\n";
    let mut spec = RecordSpec::new("s.txt");
    spec.units = Some(Units::G);
    spec.scale = -2.0;
    let rec = load_record_from_str(&spec, text).unwrap().record;
    assert_eq!(rec.acceleration, vec![0.0, -G, 0.5 * G]);
    assert_eq!(rec.scale, -2.0 * G);

    let mut spec = RecordSpec::new("s.txt");
    spec.units = Some(Units::CentimetersPerSecond2);
    spec.target_pga_g = Some(0.3);
    let rec = load_record_from_str(&spec, text).unwrap().record;
    assert!((rec.pga() - 0.3 * G).abs() < 1e-15);
    assert!((rec.acceleration[2] + 0.15 * G).abs() < 1e-15);
    assert!((rec.scale - 0.3 * G / 0.5).abs() < 1e-15, "scale = file number to m/s²");
}

#[test]
fn load_from_disk_relative_absolute_and_auto_format() {
    let dir = ground_motions();
    let file = "RSN753_LOMAP_CLS090-hor2.AT2";
    let rel = load_record(&RecordSpec::new(file), &dir).unwrap();
    let abs = load_record(&RecordSpec::new(dir.join(file)), std::path::Path::new("/elsewhere")).unwrap();
    assert_eq!(rel.record.acceleration, abs.record.acceleration);
    assert_eq!(rel.record.name, "RSN753_LOMAP_CLS090-hor2");
    assert_eq!(rel.record.source, file);
    assert_eq!(rel.record.header[1], "Loma Prieta, 10/18/1989, Corralitos, 90");
    assert!(rel.warnings.is_empty(), "{:?}", rel.warnings);
    // first value as written in the file: .1765551E-02 g
    assert_eq!(rel.record.acceleration[0], 0.1765551e-2 * G);

    let mut spec = RecordSpec::new(format!("../ground_motions/{file}"));
    spec.name = Some("Corralitos 090".into());
    let named = load_record(&spec, &dir.join("../docs")).unwrap();
    assert_eq!(named.record.name, "Corralitos 090");
    assert_eq!(named.record.acceleration, rel.record.acceleration);

    // format resolution
    let fmt = |f: &str, dt: Option<f64>| {
        let mut s = RecordSpec::new(f);
        s.dt = dt;
        s.resolved_format()
    };
    assert_eq!(fmt("a.AT2", None), Format::At2);
    assert_eq!(fmt("a.at2", None), Format::At2);
    assert_eq!(fmt("a.txt", Some(0.01)), Format::OneColumn);
    assert_eq!(fmt("a.csv", None), Format::TwoColumn);
    let spec: RecordSpec = toml::from_str("file = \"a.dat\"\nformat = \"at2\"\n").unwrap();
    assert_eq!(spec.resolved_format(), Format::At2);
    let spec: RecordSpec = toml::from_str("file = \"a.dat\"\nformat = \"two-column\"\ncolumn = 3\n").unwrap();
    assert_eq!((spec.format, spec.column), (Format::TwoColumn, Some(3)));
}

/// AT2 header line 3 in the spellings of other databases and hand-made
/// files: the units stated there are used (a file in gal read as g would
/// be 981 times too strong), a `units` that agrees is accepted, one that
/// contradicts is refused, and a header without units or with units not
/// recognised needs `units`.
#[test]
fn at2_units_are_read_from_the_header_and_never_guessed() {
    let body = "NPTS=   3, DT=   .0100 SEC\n0.0 1.0 -0.5\n";
    let at2 = |line3: &str| format!("PEER-like DATABASE\nEVENT, STATION\n{line3}\n{body}");
    for (line3, units, factor) in [
        ("ACCELERATION TIME SERIES IN UNITS OF G", Units::G, G),
        ("ACCELERATION TIME SERIES IN UNITS OF GAL", Units::CentimetersPerSecond2, 0.01),
        ("ACCELERATION TIME SERIES IN UNITS OF CM/S/S", Units::CentimetersPerSecond2, 0.01),
        ("ACCELERATION IN UNITS OF CM/SEC/SEC", Units::CentimetersPerSecond2, 0.01),
        ("ACCELERATION IN UNITS OF M/S/S", Units::MetersPerSecond2, 1.0),
    ] {
        let text = at2(line3);
        let mut spec = RecordSpec::new("h.AT2");
        let rec = load_record_from_str(&spec, &text).unwrap_or_else(|e| panic!("{line3}: {e}")).record;
        assert_eq!((rec.units, rec.acceleration[1]), (units, factor), "{line3}");
        spec.units = Some(units);
        assert!(load_record_from_str(&spec, &text).is_ok(), "{line3}: agreeing units are accepted");
        let other = if units == Units::G { Units::CentimetersPerSecond2 } else { Units::G };
        spec.units = Some(other);
        let err = load_record_from_str(&spec, &text).unwrap_err().to_string();
        assert!(err.contains("header says units of") && err.contains(other.name()), "{line3}: {err}");
    }
    for (line3, why) in [
        ("ACCELERATION TIME SERIES", "states no units"),
        ("ACCELERATION IN UNITS OF FURLONGS/FORTNIGHT^2", "`FURLONGS/FORTNIGHT^2` are not recognised"),
    ] {
        let text = at2(line3);
        let mut spec = RecordSpec::new("h.AT2");
        let err = load_record_from_str(&spec, &text).unwrap_err().to_string();
        assert!(err.starts_with("h.AT2: field `units`") && err.contains(why), "{line3}: {err}");
        spec.units = Some(Units::CentimetersPerSecond2);
        let loaded = load_record_from_str(&spec, &text).unwrap();
        assert_eq!(loaded.record.acceleration[1], 0.01, "{line3}: the config's units are used");
        assert!(loaded.warnings.iter().any(|w| w.contains("the config's")), "{line3}: {:?}", loaded.warnings);
    }
}

/// Records no earthquake produces are refused with the value named: a time
/// step outside 1e-5..1 s, a sample beyond 5 g (in the file as read or
/// after scaling; the limit was 20 g), a duration over a day.
#[test]
fn physically_absurd_records_are_refused() {
    let mut spec = RecordSpec::new("a.txt");
    spec.units = Some(Units::G);
    for (text, expect) in [
        ("0 0\n1e-300 0.1\n", "dt = 1e-300 s is outside"),
        ("0 0\n1e300 0.1\n", "dt = 1e300 s is outside"),
        ("0 0\n0.01 1e300\n", "beyond 5 g"),
        ("0 0\n0.01 25\n", "beyond 5 g"),
        ("0 0\n0.01 5.1\n", "sample 1 (t = 0.01 s) is 5.1 g in the file, beyond 5 g: no recorded ground motion"),
    ] {
        let err = load_record_from_str(&spec, text).unwrap_err().to_string();
        assert!(err.contains(expect), "{text:?}: {err}");
    }
    // 5 g itself and a scale that pushes a record beyond it
    assert!(load_record_from_str(&spec, "0 0\n0.01 5\n").is_ok());
    spec.scale = 2.0;
    let e = load_record_from_str(&spec, "0 0\n0.01 3\n").unwrap_err().to_string();
    assert!(
        e.contains("field `scale`: scale = 2: the scaled record reaches 6.000 g") && e.contains("beyond 5 g"),
        "{e}"
    );
    // a scale that overflows names its field too
    spec.scale = 1e308;
    let e = load_record_from_str(&spec, "0 0\n0.01 3\n").unwrap_err().to_string();
    assert!(e.contains("field `scale`: scale = 1e308: the scaled record reaches an overflow"), "{e}");
    // a day and a bit at 1 s
    let long = quakejoint_motion::Record::new("long", 1.0, vec![0.0; 86_402]).unwrap_err().to_string();
    assert!(long.contains("more than a day"), "{long}");
    assert!(quakejoint_motion::Record::new("day", 1.0, vec![0.0; 86_401]).is_ok());
}
