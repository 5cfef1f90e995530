//! Test 3: every kind of bad input gives an error (never a panic) whose
//! message names the file and the line (data errors) or the field (spec
//! errors); a record that does not start near zero gives a warning only.

use std::path::Path;

use quakejoint_motion::{
    load_record, load_record_from_str, parse_at2, parse_one_column, parse_two_column, peaks, period_range, spectrum,
    Format, Oscillator, Record, RecordError, RecordSpec, SpectrumError, SpectrumOptions, Units,
};

const HEAD: &str = "PEER NGA STRONG MOTION DATABASE RECORD\r\nTest, 1/1/2000, Station, 0\r\n\
                    ACCELERATION TIME SERIES IN UNITS OF G\r\n";

fn at2(line4: &str, body: &str) -> String {
    format!("{HEAD}{line4}\r\n{body}")
}

/// The error message of `r`, checked to start with `file:line:`.
fn at_line<T: std::fmt::Debug>(r: Result<T, RecordError>, file: &str, line: usize) -> String {
    let msg = r.unwrap_err().to_string();
    assert!(msg.starts_with(&format!("{file}:{line}: ")), "expected `{file}:{line}:` in: {msg}");
    msg
}

#[test]
fn at2_header_without_npts_or_dt() {
    let m = at_line(parse_at2(&at2("DT=   .0050 SEC", " .1 .2\r\n"), "a.AT2"), "a.AT2", 4);
    assert!(m.contains("no NPTS"), "{m}");
    let m = at_line(parse_at2(&at2("NPTS=   2,", " .1 .2\r\n"), "a.AT2"), "a.AT2", 4);
    assert!(m.contains("no DT"), "{m}");
    let m = at_line(parse_at2(&at2("NPTS= 2.5, DT= .01", " .1 .2\r\n"), "a.AT2"), "a.AT2", 4);
    assert!(m.contains("NPTS `2.5`"), "{m}");
    let m = at_line(parse_at2(&at2("NPTS= 0, DT= .01", ""), "a.AT2"), "a.AT2", 4);
    assert!(m.contains("NPTS = 0"), "{m}");
    let m = at_line(parse_at2(&at2("NPTS= 2, DT= x.01 SEC", " .1 .2\r\n"), "a.AT2"), "a.AT2", 4);
    assert!(m.contains("`x.01` is not a number"), "{m}");
    // a header cut short
    let m = at_line(parse_at2("PEER NGA\r\nevent\r\n", "short.AT2"), "short.AT2", 2);
    assert!(m.contains("4 header lines"), "{m}");
    // a velocity file is not an acceleration record
    let vt2 = "PEER\r\nev\r\nVELOCITY TIME SERIES IN UNITS OF CM/S\r\nNPTS= 1, DT= .01\r\n.1\r\n";
    let m = at_line(parse_at2(vt2, "v.VT2"), "v.VT2", 3);
    assert!(m.contains("not an acceleration record"), "{m}");
}

#[test]
fn dt_not_positive() {
    for dt in ["0.0", "-.005", "0"] {
        let m = at_line(parse_at2(&at2(&format!("NPTS= 2, DT= {dt} SEC"), " .1 .2\r\n"), "a.AT2"), "a.AT2", 4);
        assert!(m.contains("must be finite and > 0"), "{m}");
    }
    // a two-column file whose time goes backwards
    let m = at_line(parse_two_column("1.0 0.1\n0.5 0.2\n0.0 0.3\n", "t.txt", 2), "t.txt", 3);
    assert!(m.contains("dt = -0.5"), "{m}");
    // a one-column spec with dt <= 0 names the field
    let mut spec = RecordSpec::new("one.txt");
    spec.format = Format::OneColumn;
    spec.dt = Some(0.0);
    let m = load_record_from_str(&spec, "0.1\n").unwrap_err().to_string();
    assert!(m.starts_with("one.txt: field `dt`:"), "{m}");
    assert!(parse_one_column("0.1\n", "one.txt", -1.0, None).unwrap_err().to_string().contains("field `dt`"));
}

#[test]
fn value_count_differs_from_npts() {
    // fewer: the error points at the last line of the file
    let text = at2("NPTS= 7, DT= .01 SEC,", " .1 .2 .3 .4 .5\r\n .6\r\n");
    let m = at_line(parse_at2(&text, "few.AT2"), "few.AT2", 6);
    assert!(m.contains("NPTS = 7") && m.contains("after 6 values"), "{m}");
    // more: the error points at the line holding the first value too many
    let text = at2("NPTS= 5, DT= .01 SEC,", " .1 .2 .3\r\n .4 .5 .6\r\n");
    let m = at_line(parse_at2(&text, "many.AT2"), "many.AT2", 6);
    assert!(m.contains("more values than NPTS = 5") && m.contains("value number 6"), "{m}");
    // a header and no values at all
    let m = at_line(parse_at2(&at2("NPTS= 3, DT= .01", ""), "none.AT2"), "none.AT2", 4);
    assert!(m.contains("after 0 values"), "{m}");
}

#[test]
fn token_not_a_number() {
    let text = at2("NPTS= 5, DT= .01 SEC,", " .1 .2 .3\r\n .4 0.5x\r\n");
    let m = at_line(parse_at2(&text, "bad.AT2"), "bad.AT2", 6);
    assert!(m.contains("`0.5x` is not a number"), "{m}");
    let m = at_line(parse_two_column("t,a\n0,0.1\n0.01,abc\n", "bad.csv", 2), "bad.csv", 3);
    assert!(m.contains("`abc`"), "{m}");
    let m = at_line(parse_two_column("0 0.1\n0.01x 0.2\n", "bad.txt", 2), "bad.txt", 2);
    assert!(m.contains("`0.01x`"), "{m}");
    let m = at_line(parse_one_column("0.1\n0.2\n--3\n", "bad.txt", 0.01, None), "bad.txt", 3);
    assert!(m.contains("`--3`"), "{m}");
}

#[test]
fn nan_and_infinity() {
    for tok in ["NaN", "nan", "inf", "-Infinity", "1e400"] {
        let text = at2("NPTS= 3, DT= .01 SEC,", &format!(" .1\r\n .2 {tok}\r\n"));
        let m = at_line(parse_at2(&text, "nan.AT2"), "nan.AT2", 6);
        assert!(m.contains(&format!("`{tok}` is not a finite number")), "{m}");
    }
    let m = at_line(parse_two_column("0 0.1\n0.01 NaN\n", "n.txt", 2), "n.txt", 2);
    assert!(m.contains("`NaN`"), "{m}");
    let m = at_line(parse_one_column("0.1\ninf\n", "n.txt", 0.01, None), "n.txt", 2);
    assert!(m.contains("`inf`"), "{m}");
    let m = at_line(parse_at2(&at2("NPTS= 1, DT= NaN", ".1\r\n"), "n.AT2"), "n.AT2", 4);
    assert!(m.contains("`NaN`"), "{m}");
}

#[test]
fn empty_files() {
    for text in ["", "   \r\n\r\n", "\u{feff}"] {
        for r in
            [parse_at2(text, "e.AT2"), parse_two_column(text, "e.AT2", 2), parse_one_column(text, "e.AT2", 0.01, None)]
        {
            assert_eq!(r.unwrap_err().to_string(), "e.AT2: the file is empty");
        }
    }
    // only comments and a column header: no data
    let m = parse_two_column("# nothing\ntime,acc\n", "c.csv", 2).unwrap_err().to_string();
    assert!(m.starts_with("c.csv: ") && m.contains("no data lines"), "{m}");
    // a single sample cannot give dt
    let m = parse_two_column("0 1\n", "one.txt", 2).unwrap_err().to_string();
    assert!(m.starts_with("one.txt: ") && m.contains("at least 2 samples"), "{m}");
}

#[test]
fn non_uniform_time_column() {
    let m = at_line(parse_two_column("0 1\n0.01 2\n0.025 3\n0.03 4\n", "nu.txt", 2), "nu.txt", 3);
    assert!(m.contains("not uniform") && m.contains("t = 0.025"), "{m}");
    // drift within 1 % of dt (rounded printing) is accepted
    let r = parse_two_column("0 1\n0.01005 2\n0.02 3\n", "ok.txt", 2).unwrap();
    assert_eq!(r.dt, 0.01);
    // with a comment and a header line before: line numbers stay those of the file
    let m = at_line(parse_two_column("# c\ntime acc\n0 1\n0.01 2\n0.05 3\n0.03 4\n", "nu.txt", 2), "nu.txt", 5);
    assert!(m.contains("t = 0.05"), "{m}");
}

#[test]
fn wrong_column_counts() {
    let m = at_line(parse_two_column("0 1 2\n0.01 2\n", "c.txt", 3), "c.txt", 2);
    assert!(m.contains("column 3"), "{m}");
    let m = at_line(parse_one_column("0.1\n0.2 0.3\n", "c.txt", 0.01, None), "c.txt", 2);
    assert!(m.contains("one value per line"), "{m}");
    let m = at_line(parse_two_column("0,1\n0.01,,2\n", "c.csv", 2), "c.csv", 2);
    assert!(m.contains("empty field"), "{m}");
}

#[test]
fn spec_errors_name_the_field() {
    let check = |spec: &RecordSpec, field: &str| {
        let m = load_record_from_str(spec, "0 0.1\n0.01 0.2\n").unwrap_err().to_string();
        assert!(m.starts_with(&format!("{}: field `{field}`:", spec.file.display())), "{m}");
        // load_record checks the spec before opening the file
        let m2 = load_record(spec, Path::new("/nonexistent")).unwrap_err().to_string();
        assert_eq!(m, m2);
    };
    let mut s = RecordSpec::new("r.AT2");
    s.dt = Some(0.01);
    check(&s, "dt");
    let mut s = RecordSpec::new("r.csv");
    s.format = Format::TwoColumn;
    s.dt = Some(0.01);
    check(&s, "dt");
    let mut s = RecordSpec::new("r.txt");
    s.format = Format::OneColumn;
    check(&s, "dt");
    let mut s = RecordSpec::new("r.txt");
    s.dt = Some(f64::NAN);
    check(&s, "dt");
    let mut s = RecordSpec::new("r.AT2");
    s.column = Some(2);
    check(&s, "column");
    let mut s = RecordSpec::new("r.csv");
    s.column = Some(1);
    check(&s, "column");
    let mut s = RecordSpec::new("r.csv");
    s.scale = 0.0;
    check(&s, "scale");
    let mut s = RecordSpec::new("r.csv");
    s.scale = f64::INFINITY;
    check(&s, "scale");
    let mut s = RecordSpec::new("r.csv");
    s.target_pga_g = Some(-0.3);
    check(&s, "target_pga_g");
    let mut s = RecordSpec::new("r.csv");
    s.target_pga_g = Some(0.3);
    s.scale = 2.0;
    check(&s, "target_pga_g");
    // a zero record cannot be scaled to a PGA
    let mut s = RecordSpec::new("zero.csv");
    s.target_pga_g = Some(0.3);
    s.units = Some(Units::G);
    let m = load_record_from_str(&s, "0 0\n0.01 0\n").unwrap_err().to_string();
    assert!(m.starts_with("zero.csv: field `target_pga_g`:"), "{m}");
}

#[test]
fn toml_spec_errors() {
    let e = toml::from_str::<RecordSpec>("file = \"a.AT2\"\nscal = 2.0\n").unwrap_err().to_string();
    assert!(e.contains("scal"), "{e}");
    let e = toml::from_str::<RecordSpec>("file = \"a.AT2\"\nunits = \"furlong/fortnight2\"\n").unwrap_err().to_string();
    assert!(e.contains("furlong"), "{e}");
    // gal is cm/s2
    let s: RecordSpec = toml::from_str("file = \"a.AT2\"\nunits = \"gal\"\n").unwrap();
    assert_eq!(s.units, Some(Units::CentimetersPerSecond2));
    let e = toml::from_str::<RecordSpec>("units = \"g\"\n").unwrap_err().to_string();
    assert!(e.contains("file"), "{e}");
    let s: RecordSpec =
        toml::from_str("file = \"x.txt\"\nformat = \"one-column\"\nunits = \"cm/s2\"\ndt = 0.01\ntarget_pga_g = 0.4\n")
            .unwrap();
    assert_eq!(
        (s.format, s.units, s.dt, s.scale, s.target_pga_g),
        (Format::OneColumn, Some(Units::CentimetersPerSecond2), Some(0.01), 1.0, Some(0.4))
    );
}

#[test]
fn missing_file_is_named() {
    let m = load_record(&RecordSpec::new("no_such_record.AT2"), Path::new("/nonexistent/dir")).unwrap_err().to_string();
    assert!(m.starts_with("no_such_record.AT2 (/nonexistent/dir/no_such_record.AT2): cannot read"), "{m}");
}

#[test]
fn start_warning_not_error() {
    let mut spec = RecordSpec::new("start.txt");
    spec.dt = Some(0.01);
    spec.units = Some(Units::G);
    // a[0] = 0.02 = 2 % of PGA 1.0: warning
    let loaded = load_record_from_str(&spec, "0.02\n1.0\n-0.5\n").unwrap();
    assert_eq!(loaded.warnings.len(), 1, "{:?}", loaded.warnings);
    let w = &loaded.warnings[0];
    assert!(w.starts_with("start.txt: the record does not start near zero") && w.contains("threshold 1 %"), "{w}");
    // a[0] = 0.5 % of PGA: no warning
    assert!(load_record_from_str(&spec, "0.005\n1.0\n-0.5\n").unwrap().warnings.is_empty());
}

#[test]
fn invalid_records_and_spectrum_arguments() {
    let m = Record::new("r", 0.0, vec![1.0]).unwrap_err().to_string();
    assert!(m.starts_with("record `r`:") && m.contains("dt = 0"), "{m}");
    assert!(Record::new("r", 0.01, vec![]).unwrap_err().to_string().contains("at least 2 are needed"));
    let m = Record::new("r", 0.01, vec![0.0, f64::NAN]).unwrap_err().to_string();
    assert!(m.contains("sample 1"), "{m}");

    let rec = Record::new("r", 0.01, vec![0.0, 1.0, 0.0]).unwrap();
    let o = SpectrumOptions::default();
    assert_eq!(spectrum(&rec, &[-1.0], &[0.05], o), Err(SpectrumError::Period(-1.0)));
    assert!(matches!(spectrum(&rec, &[f64::NAN], &[0.05], o), Err(SpectrumError::Period(_))));
    assert_eq!(spectrum(&rec, &[1.0], &[1.0], o), Err(SpectrumError::Damping(1.0)));
    assert_eq!(spectrum(&rec, &[1.0], &[-0.01], o), Err(SpectrumError::Damping(-0.01)));
    assert_eq!(
        spectrum(&rec, &[1.0], &[0.05], SpectrumOptions { subdivisions: 5000 }),
        Err(SpectrumError::Subdivisions(5000))
    );
    let mut bad = rec.clone();
    bad.dt = -0.01;
    assert_eq!(spectrum(&bad, &[1.0], &[0.05], o), Err(SpectrumError::Dt(-0.01)));
    bad.dt = 0.01;
    bad.acceleration.clear();
    assert!(matches!(spectrum(&bad, &[1.0], &[0.05], o), Err(SpectrumError::Record(_))));
    assert!(Oscillator::new(1.0, 0.05, 0.01).unwrap().peaks(&[0.0, f64::INFINITY], o).is_err());
    // the unchecked entry points answer NaN instead of panicking
    assert!(peaks(&[1.0, 2.0], 0.01, -1.0, 0.05, o).sa.is_nan());
    assert!(peaks(&[], 0.01, 1.0, 0.05, o).sd.is_nan());
    assert!(quakejoint_motion::history(&[1.0, 2.0], 0.0, 1.0, 0.05).u.iter().all(|x| x.is_nan()));

    for (from, to, count, log) in [
        (0.0, 1.0, 10, true),
        (-1.0, 1.0, 10, false),
        (2.0, 1.0, 10, true),
        (0.1, 1.0, 0, true),
        (0.1, 1.0, 1, true),
        (0.1, f64::INFINITY, 5, false),
    ] {
        let e = period_range(from, to, count, log).unwrap_err();
        assert!(e.to_string().starts_with("period range: "), "{e}");
    }
}

/// A positive period below a microsecond is refused (its `w^2` overflows:
/// 1e-154 s gave an infinite Sa, 1e-300 s a Sa of 0), while 0 is the
/// rigid oscillator and 1e-6 s responds as it does, with the ground
/// (Sa = PGA to 1e-6).
#[test]
fn periods_below_a_microsecond_are_refused() {
    let acc: Vec<f64> = (0..400).map(|i| (0.05 * i as f64).sin() * (1.0 - i as f64 / 400.0)).collect();
    let pga = acc.iter().fold(0.0f64, |m, a| m.max(a.abs()));
    for t in [1e-300, 1e-154, 5e-7] {
        let e = quakejoint_motion::spectrum_samples(&acc, 0.01, &[t], &[0.05], Default::default()).unwrap_err();
        assert!(e.to_string().contains("1e-6 s"), "{t}: {e}");
    }
    let rows = quakejoint_motion::spectrum_samples(&acc, 0.01, &[0.0, 1e-6], &[0.05], Default::default()).unwrap();
    for r in rows {
        assert!((r.peaks.sa - pga).abs() <= 1e-6 * pga, "{}: {} against {pga}", r.period, r.peaks.sa);
    }
}
