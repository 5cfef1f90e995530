//! Records of other databases than PEER: ESM ASCII, K-NET/KiK-net ASCII,
//! COSMOS V2 and a sequence of values, read from realistic files and
//! checked against the PEER AT2 of the same record (Loma Prieta 1989,
//! Corralitos 090): the same dt, the same PGA to the rounding of the
//! format.
//!
//! Two kinds of file: the fixtures in `tests/data/` (a 320-sample window
//! holding the PGA, with headers as the databases write them, written by
//! `tests/data/make_fixtures.py` from the AT2), read from disk with
//! `format = "auto"`; and the whole record written here in each format.
//! Then small inline files for each format's rules.

mod common;

use common::ground_motions;
use quakejoint_motion::{
    load_record, load_record_from_str, parse_at2, Format, HeaderUnits, RecordSpec, Units, G, MAX_ACCELERATION_G,
};

/// The AT2 record in gal and its dt.
fn at2_gal() -> (Vec<f64>, f64) {
    let text = std::fs::read_to_string(ground_motions().join("RSN753_LOMAP_CLS090-hor2.AT2")).unwrap();
    let raw = parse_at2(&text, "at2").unwrap();
    (raw.values.iter().map(|g| g * G * 100.0).collect(), raw.dt)
}

fn peak(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// The window of the fixtures: samples 700..1020 (t = 3.5..5.095 s).
const FIRST: usize = 700;
const COUNT: usize = 320;

fn data_dir() -> std::path::PathBuf {
    std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data")
}

#[test]
fn fixtures_agree_with_the_at2() {
    let (gal, dt) = at2_gal();
    let window = &gal[FIRST..FIRST + COUNT];
    let pga = peak(window);
    assert!((pga - peak(&gal)).abs() < 1e-12, "the window holds the record's PGA");
    let mean = window.iter().sum::<f64>() / COUNT as f64;
    let pga_demeaned = window.iter().fold(0.0f64, |m, x| m.max((x - mean).abs()));
    let knet_count = 3920.0 / 6182761.0; // gal
                                         // the window starts at 55 % of the PGA: every file warns of that
    let start = "the record does not start near zero";
    for (file, format, want_pga, tolerance, warnings) in [
        ("CE.CLS..HGE.D.19891018.000415.C.ACC.ASC", Format::Esm, pga, 1e-6 * pga, vec![start]),
        // counts are rounded to one count; the window's mean is removed
        ("CLS0001910181704.EW", Format::Knet, pga_demeaned, knet_count, vec!["the record's mean", start]),
        // (8F10.5): 5 decimals of gal, the values below -100 touching
        ("CLS090.V2", Format::Cosmos, pga, 5e-6, vec![start]),
    ] {
        let loaded = load_record(&RecordSpec::new(file), &data_dir()).unwrap_or_else(|e| panic!("{file}: {e}"));
        let rec = &loaded.record;
        println!(
            "{file}: {:?}, dt = {} s, n = {}, PGA = {:.4} gal (AT2 {:.4} gal), warnings {:?}",
            loaded.format,
            rec.dt,
            rec.acceleration.len(),
            rec.pga() * 100.0,
            want_pga,
            loaded.warnings
        );
        assert_eq!(loaded.format, format, "{file}");
        assert!((rec.dt - dt).abs() < 1e-15, "{file}: dt {}", rec.dt);
        assert_eq!(rec.acceleration.len(), COUNT, "{file}");
        assert_eq!((rec.units, rec.user_scale), (Units::CentimetersPerSecond2, 1.0), "{file}");
        assert!((rec.file_pga - want_pga).abs() <= tolerance, "{file}: file PGA {} vs {want_pga}", rec.file_pga);
        assert!((rec.pga() * 100.0 - want_pga).abs() <= tolerance, "{file}: PGA {} gal", rec.pga() * 100.0);
        assert_eq!(loaded.warnings.len(), warnings.len(), "{file}: {:?}", loaded.warnings);
        for (w, want) in loaded.warnings.iter().zip(&warnings) {
            assert!(w.starts_with(&format!("{file}: {want}")), "{file}: {w}");
        }
        assert!(!rec.header.is_empty(), "{file}: header kept");
    }
    // the same PGA in g as PROVENANCE.md gives for the AT2: 0.4828 g
    let esm = load_record(&RecordSpec::new("CE.CLS..HGE.D.19891018.000415.C.ACC.ASC"), &data_dir()).unwrap();
    assert_eq!(format!("{:.4}", esm.record.pga() / G), "0.4828");
}

/// `x` as `1.731414E+00` (C's `%.6E`, as the databases write).
fn sci(x: f64) -> String {
    let s = format!("{x:.6E}");
    let (m, e) = s.split_once('E').unwrap();
    let e: i32 = e.parse().unwrap();
    format!("{m}E{}{:02}", if e < 0 { '-' } else { '+' }, e.abs())
}

/// The whole record in each format, written here from the AT2 (values in
/// gal), read back: dt and PGA as the AT2's to the format's rounding.
#[test]
fn whole_record_in_each_format() {
    let (gal, dt) = at2_gal();
    let n = gal.len();
    let pga = peak(&gal);
    let esm = format!(
        "EVENT_NAME: LOMA PRIETA\nEVENT_ID: X\nSAMPLING_INTERVAL_S: 0.005000\nNDATA: {n}\nSTREAM: HGE\nUNITS: cm/s^2\n\
         PGA_CM/S^2: {pga:.6}\nDATA_TYPE: ACCELERATION\nUSER5: \n{}\n",
        gal.iter().map(|v| sci(*v)).collect::<Vec<_>>().join("\n")
    );
    let factor = 3920.0 / 6182761.0;
    let counts: Vec<i64> = gal.iter().map(|v| (v / factor).round() as i64 + 1234).collect();
    let knet_body: Vec<String> =
        counts.chunks(8).map(|c| c.iter().map(|x| format!("{x:9}")).collect::<String>()).collect();
    let knet = format!(
        "Origin Time       1989/10/18 17:04:00\nSampling Freq(Hz) 200Hz\nDuration Time(s)  40\nDir.              E-W\n\
         Scale Factor      3920(gal)/6182761\nMax. Acc. (gal)   {pga:.3}\nMemo.\n{}\n",
        knet_body.join("\n")
    );
    // the body alone, 8 per line, as a sequence
    let seq_body: Vec<String> =
        gal.chunks(8).map(|c| c.iter().map(|x| format!("{x:10.5}")).collect::<String>()).collect();
    let sequence = seq_body.join("\n");
    let csv = format!(
        "time,acc_cm_s2\n{}\n",
        gal.iter().enumerate().map(|(i, v)| format!("{:.3},{v:.6}", i as f64 * dt)).collect::<Vec<_>>().join("\n")
    );
    let mean = gal.iter().sum::<f64>() / n as f64;
    let pga_demeaned = gal.iter().fold(0.0f64, |m, x| m.max((x - mean).abs()));
    let spec = |file: &str, format: Format, units: Option<Units>, dt: Option<f64>| {
        let mut s = RecordSpec::new(file);
        (s.format, s.units, s.dt) = (format, units, dt);
        s
    };
    let gal_units = Some(Units::CentimetersPerSecond2);
    for (what, s, text, want_format, want_pga, tolerance) in [
        ("ESM", spec("r.ASC", Format::Auto, None, None), esm, Format::Esm, pga, 1e-6 * pga),
        ("K-NET", spec("r.EW", Format::Auto, None, None), knet, Format::Knet, pga_demeaned, factor),
        ("sequence", spec("r.txt", Format::Sequence, gal_units, Some(dt)), sequence, Format::Sequence, pga, 5e-6),
        ("CSV", spec("r.csv", Format::Auto, gal_units, None), csv, Format::TwoColumn, pga, 5e-7),
    ] {
        let loaded = load_record_from_str(&s, &text).unwrap_or_else(|e| panic!("{what}: {e}"));
        let rec = &loaded.record;
        println!(
            "{what}: dt = {}, n = {}, PGA = {:.6} gal, warnings {:?}",
            rec.dt,
            rec.acceleration.len(),
            rec.pga() * 100.0,
            loaded.warnings
        );
        assert_eq!(loaded.format, want_format, "{what}");
        assert_eq!((rec.acceleration.len(), rec.dt), (n, dt), "{what}");
        assert!((rec.pga() * 100.0 - want_pga).abs() <= tolerance, "{what}: PGA {} vs {want_pga}", rec.pga() * 100.0);
        assert!((rec.pga() / G - 0.4828).abs() < 5e-5, "{what}: 0.4828 g as in PROVENANCE.md");
    }
}

#[test]
fn esm_rules() {
    let esm = |units: &str, data_type: &str, ndata: usize, pga: &str, data: &str| {
        format!(
            "EVENT_NAME: T\nSAMPLING_INTERVAL_S: 0.01\nNDATA: {ndata}\nSTREAM: HNE\nUNITS: {units}\nPGA_CM/S^2: {pga}\n\
             DATA_TYPE: {data_type}\nUSER5: \n{data}"
        )
    };
    let ok = esm("cm/s^2", "ACCELERATION", 3, "2.0", "1.0E+00\n-2.0E+00\n0.5E+00\n");
    let loaded = load_record_from_str(&RecordSpec::new("a.ASC"), &ok).unwrap();
    assert_eq!(loaded.format, Format::Esm);
    assert_eq!((loaded.record.dt, loaded.record.acceleration.clone()), (0.01, vec![0.01, -0.02, 0.005]));
    assert_eq!(loaded.record.units, Units::CentimetersPerSecond2);
    // `units` must agree with the header
    let mut spec = RecordSpec::new("a.ASC");
    spec.units = Some(Units::G);
    let e = load_record_from_str(&spec, &ok).unwrap_err().to_string();
    assert!(e.starts_with("a.ASC: field `units`: the file's header says units of cm/s2"), "{e}");
    // NDATA against the data: both numbers named
    let e = load_record_from_str(&RecordSpec::new("a.ASC"), &esm("cm/s^2", "ACCELERATION", 4, "2", "1\n2\n3\n"))
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("a.ASC:3: the header says NDATA = 4 but the file holds 3 values"), "{e}");
    // not acceleration: the value named
    for kind in ["VELOCITY", "DISPLACEMENT", "ACCELERATION RESPONSE SPECTRUM"] {
        let text = esm("cm/s", kind, 3, "", "1\n2\n3\n");
        let e = load_record_from_str(&RecordSpec::new("v.ASC"), &text).unwrap_err().to_string();
        assert!(e.starts_with(&format!("v.ASC:7: DATA_TYPE is `{kind}`: not an acceleration record")), "{e}");
    }
    // unknown or missing units are never guessed
    let odd = esm("mm/s^2", "ACCELERATION", 3, "", "1\n2\n3\n");
    let e = load_record_from_str(&RecordSpec::new("u.ASC"), &odd).unwrap_err().to_string();
    assert!(e.contains("field `units`: the header's units `mm/s^2` are not recognised"), "{e}");
    let none = esm("", "ACCELERATION", 3, "", "1\n2\n3\n");
    let e = load_record_from_str(&RecordSpec::new("u.ASC"), &none).unwrap_err().to_string();
    assert!(e.contains("field `units`: the header states no units (no `UNITS:` value)"), "{e}");
    let mut spec = RecordSpec::new("u.ASC");
    spec.units = Some(Units::MetersPerSecond2);
    assert_eq!(load_record_from_str(&spec, &none).unwrap().record.acceleration[2], 3.0);
    // a header PGA 1 % off warns; within 1 % does not
    let off = esm("cm/s^2", "ACCELERATION", 3, "2.03", "0\n-2\n0.5\n");
    let w = load_record_from_str(&RecordSpec::new("p.ASC"), &off).unwrap().warnings;
    assert!(w.iter().any(|w| w.starts_with("p.ASC: the header's PGA_CM/S^2 = 2.03 cm/s²")), "{w:?}");
    let near = esm("cm/s^2", "ACCELERATION", 3, "2.019", "0\n-2\n0.5\n");
    assert!(load_record_from_str(&RecordSpec::new("p.ASC"), &near).unwrap().warnings.is_empty());
}

fn knet(freq: &str, dir: &str, scale: &str, max: &str, data: &str) -> String {
    format!(
        "Origin Time       2008/06/14 08:43:00\nLat.              39.030\nStation Code      IWT000\n\
         Sampling Freq(Hz) {freq}\nDuration Time(s)  0\nDir.              {dir}\nScale Factor      {scale}\n\
         Max. Acc. (gal)   {max}\nLast Correction   2008/06/14 08:43:00\nMemo.\n{data}"
    )
}

#[test]
fn knet_rules() {
    // counts 1000 + (0, 8, -8, 0) at 2000 gal / 1000 counts = 2 gal per count
    let text = knet("100Hz", "N-S", "2000(gal)/1000", "16", "     1000     1008      992     1000\n");
    let loaded = load_record_from_str(&RecordSpec::new("IWT0000806140843.NS"), &text).unwrap();
    assert_eq!(loaded.format, Format::Knet);
    let rec = &loaded.record;
    assert_eq!((rec.dt, rec.units), (0.01, Units::CentimetersPerSecond2));
    assert_eq!(rec.acceleration, vec![0.0, 0.16, -0.16, 0.0], "mean (2000 gal) removed, then gal to m/s²");
    assert_eq!(rec.file_pga, 16.0);
    assert_eq!(loaded.warnings.len(), 1, "{:?}", loaded.warnings);
    assert!(loaded.warnings[0].contains("the record's mean, 2000.0000 gal (1000.00 counts), was removed"));
    // Max. Acc. 5 % off; a vertical component; KiK-net borehole
    let text = knet("100Hz", "U-D", "2000(gal)/1000", "16.8", "1000 1008 992 1000\n");
    let e = load_record_from_str(&RecordSpec::new("k.UD"), &text).unwrap_err().to_string();
    assert!(e.contains("field `allow_vertical`") && e.contains("vertical") && e.contains("horizontal"), "{e}");
    let mut vertical = RecordSpec::new("k.UD");
    vertical.allow_vertical = true;
    let w = load_record_from_str(&vertical, &text).unwrap().warnings;
    assert!(w.iter().any(|w| w.contains("Max. Acc. (gal) = 16.8 gal but the data peak at 16.0000 gal")), "{w:?}");
    assert!(w.iter().any(|w| w.contains("vertical component, read as asked")), "{w:?}");
    let text = knet("200Hz", "2", "2000(gal)/1000", "16", "1000 1008 992 1000\n");
    let loaded = load_record_from_str(&RecordSpec::new("k.EW1"), &text).unwrap();
    assert_eq!(loaded.record.dt, 0.005);
    assert!(loaded.warnings.iter().any(|w| w.contains("borehole")), "{:?}", loaded.warnings);
    // the scale factor's numerator must be in gal; `units` must agree (gal)
    let text = knet("100Hz", "E-W", "2000(cm/s2)/1000", "16", "1000 1008\n");
    let e = load_record_from_str(&RecordSpec::new("k.EW"), &text).unwrap_err().to_string();
    assert!(e.starts_with("k.EW:7: the scale factor `2000(cm/s2)/1000` is in `cm/s2` per count, not gal"), "{e}");
    let mut spec = RecordSpec::new("k.EW");
    spec.units = Some(Units::G);
    let text = knet("100Hz", "E-W", "2000(gal)/1000", "16", "1000 1008\n");
    assert!(load_record_from_str(&spec, &text).unwrap_err().to_string().contains("header says units of cm/s2"));
    spec.units = Some(Units::CentimetersPerSecond2);
    assert!(load_record_from_str(&spec, &text).is_ok());
}

#[test]
fn sequence_rules() {
    let mut spec = RecordSpec::new("body.txt");
    spec.format = Format::Sequence;
    // dt and units are required
    let e = load_record_from_str(&spec, "1 2 3\n").unwrap_err().to_string();
    assert!(e.starts_with("body.txt: field `dt`: a sequence of values needs the time step `dt`"), "{e}");
    spec.dt = Some(0.01);
    let e = load_record_from_str(&spec, "1 2 3\n").unwrap_err().to_string();
    assert!(e.starts_with("body.txt: field `units`: a text record cannot say its units"), "{e}");
    spec.units = Some(Units::CentimetersPerSecond2);
    // any number per line, in reading order; Fortran fields without a space
    let rec =
        load_record_from_str(&spec, "   1.00000   2.00000   3.00000\n  -4.00000-105.00000\n   6.0\n").unwrap().record;
    assert_eq!(rec.acceleration, vec![0.01, 0.02, 0.03, -0.04, -1.05, 0.06]);
    // counts (whole numbers) warn
    let counts: String = (0..20).map(|i| format!("{} ", 100 + i)).collect();
    let w = load_record_from_str(&spec, &counts).unwrap().warnings;
    assert!(w.iter().any(|w| w.contains("every value is a whole number")), "{w:?}");
    // `column` is not for sequences
    spec.column = Some(1);
    let e = load_record_from_str(&spec, "1 2\n").unwrap_err().to_string();
    assert!(e.starts_with("body.txt: field `column`: `column` is only for one- and two-column text files"), "{e}");
}

/// A COSMOS V2 file of 6 values at 10 ms in (3F10.5), integer header
/// values 2 and 3 and real header values 62..64 as given.
fn cosmos(physical: i32, units_code: i32, dt_ms: f64, peak: f64) -> String {
    let mut ints = [-999i32; 100];
    (ints[1], ints[2]) = (physical, units_code);
    let mut reals = [-999.0f64; 100];
    (reals[61], reals[62], reals[63]) = (dt_ms, 6.0 * dt_ms / 1000.0, peak);
    let mut t = String::from("Corrected acceleration  (Format v01.20 with 13 text lines) Src: test\n");
    for i in 2..=12 {
        t += &format!("text line {i}\n");
    }
    t += "Values used when parameter or data value is unknown/unspecified:   -999, -999.0\n";
    t += " 100 Integer-header values follow on 10 lines, Format= (10I8)\n";
    for row in ints.chunks(10) {
        t += &(row.iter().map(|v| format!("{v:8}")).collect::<String>() + "\n");
    }
    t += " 100 Real-header values follow on 17 lines, Format= (6F13.6)\n";
    for row in reals.chunks(6) {
        t += &(row.iter().map(|v| format!("{v:13.6}")).collect::<String>() + "\n");
    }
    t += "   1 Comment line(s) follow, each starting with a \"|\":\n| test\n";
    t += "       6 acceleration pts, approx    0 secs, units=cm/sec2 (04), Format=(3F10.5)\n";
    t + "   1.00000  -2.00000-300.00000\n   4.00000   5.00000   6.00000\nEnd-of-data for Chan  1 acceleration\n"
}

#[test]
fn cosmos_rules() {
    let loaded = load_record_from_str(&RecordSpec::new("c.V2"), &cosmos(1, 4, 10.0, -300.0)).unwrap();
    assert_eq!(loaded.format, Format::Cosmos);
    let rec = &loaded.record;
    assert_eq!((rec.dt, rec.units, rec.file_pga), (0.01, Units::CentimetersPerSecond2, 300.0));
    assert_eq!(rec.acceleration, vec![0.01, -0.02, -3.0, 0.04, 0.05, 0.06]);
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    // the time step is never derived from "approx ... secs"
    let e = load_record_from_str(&RecordSpec::new("c.V2"), &cosmos(1, 4, -999.0, 300.0)).unwrap_err().to_string();
    assert!(e.starts_with("c.V2:36: the sampling interval (real-header value 62) is -999 ms"), "{e}");
    // velocity; a units code other than the data line's
    let e = load_record_from_str(&RecordSpec::new("c.V2"), &cosmos(2, 4, 10.0, 300.0)).unwrap_err().to_string();
    assert!(e.contains("integer-header value 2 (physical parameter) is 2, not 1 (acceleration)"), "{e}");
    let e = load_record_from_str(&RecordSpec::new("c.V2"), &cosmos(1, 2, 10.0, 300.0)).unwrap_err().to_string();
    assert!(e.contains("units code 4 (`cm/sec2`) differs from integer-header value 3 (2)"), "{e}");
    // a peak that disagrees
    let w = load_record_from_str(&RecordSpec::new("c.V2"), &cosmos(1, 4, 10.0, 250.0)).unwrap().warnings;
    assert!(w.iter().any(|w| w.contains("peak (real-header value 64) = 250")), "{w:?}");
}

#[test]
fn formats_carrying_their_time_step_refuse_dt_and_column() {
    let esm = "EVENT_NAME: T\nSAMPLING_INTERVAL_S: 0.01\nUNITS: cm/s^2\nDATA_TYPE: ACCELERATION\n1\n2\n";
    let knet_text = knet("100Hz", "E-W", "2000(gal)/1000", "1", "1000 1001\n");
    for (file, text) in [("e.ASC", esm.to_string()), ("k.EW", knet_text), ("c.V2", cosmos(1, 4, 10.0, 300.0))] {
        let mut spec = RecordSpec::new(file);
        spec.dt = Some(0.01);
        let e = load_record_from_str(&spec, &text).unwrap_err().to_string();
        assert!(e.starts_with(&format!("{file}: field `dt`: `dt` is only for one-column and sequence files")), "{e}");
        let mut spec = RecordSpec::new(file);
        spec.column = Some(2);
        let e = load_record_from_str(&spec, &text).unwrap_err().to_string();
        assert!(e.starts_with(&format!("{file}: field `column`:")), "{e}");
    }
    // explicit formats
    for (name, format) in [
        ("esm", Format::Esm),
        ("knet", Format::Knet),
        ("k-net", Format::Knet),
        ("cosmos", Format::Cosmos),
        ("sequence", Format::Sequence),
    ] {
        let spec: RecordSpec = toml::from_str(&format!("file = \"x\"\nformat = \"{name}\"\n")).unwrap();
        assert_eq!(spec.format, format, "{name}");
    }
    let mut spec = RecordSpec::new("x.txt");
    spec.format = Format::Esm;
    let e = load_record_from_str(&spec, "0 1\n0.01 2\n").unwrap_err().to_string();
    assert!(e.starts_with("x.txt:"), "{e}");
    assert_eq!(MAX_ACCELERATION_G, 5.0);
    let _ = HeaderUnits::Missing;
}
