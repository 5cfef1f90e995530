//! Real CESMD records in the CSMIP/DMG format (`ground_motions/cesmd/`,
//! `PROVENANCE.md` there), and multi-channel COSMOS files.
//!
//! Each file is checked against what its own header says, written by
//! CSMIP's processing, not by this reader: the number of points, the
//! sampling, the units, and the peak acceleration and its time. A Volume 1
//! file of the 2019 Ridgecrest M7.1 earthquake holds three channels (90°,
//! 360°, up): each is read by number and by azimuth, the vertical one is
//! refused unless asked for, and every refusal says how to choose.

mod common;

use common::ground_motions;
use quakejoint_motion::{load_record, load_record_from_str, Format, Orientation, RecordSpec, Units, G};

fn cesmd() -> std::path::PathBuf {
    ground_motions().join("cesmd")
}

fn spec(file: &str, f: impl FnOnce(&mut RecordSpec)) -> RecordSpec {
    let mut s = RecordSpec::new(file);
    f(&mut s);
    s
}

/// Largest |a| and its time.
fn peak(a: &[f64], dt: f64) -> (f64, f64) {
    let i = (0..a.len()).max_by(|&i, &j| a[i].abs().total_cmp(&a[j].abs())).unwrap();
    (a[i].abs(), i as f64 * dt)
}

#[test]
fn ridgecrest_volume_1_every_channel_by_number_and_by_azimuth() {
    // header: No. of Points = 31932, 100 Samples/sec, Max = .344 g at
    // 234.360 s (channel 1); Max = .511 g at 235.700 s (channel 2)
    let expected = [(1, 90.0, 31932, 0.344, 234.36), (2, 360.0, 32080, 0.511, 235.70)];
    for (number, azimuth, n, max_g, t_max) in expected {
        for s in [
            spec("CICLC.v1", |s| s.channel = Some(number)),
            spec("CICLC.v1", |s| s.azimuth = Some(azimuth)),
            spec("CICLC.v1", |s| s.azimuth = Some(azimuth % 360.0)),
        ] {
            let loaded = load_record(&s, &cesmd()).unwrap();
            assert_eq!(loaded.format, Format::Csmip, "detected from the content");
            let c = loaded.channel.as_ref().unwrap();
            assert_eq!((c.number, c.of), (number, 3));
            assert_eq!(c.orientation, Orientation::Azimuth { degrees: azimuth });
            let r = &loaded.record;
            assert_eq!((r.acceleration.len(), r.dt, r.units), (n, 0.01, Units::G));
            let (pga, t) = peak(&r.acceleration, r.dt);
            assert!((pga / G - max_g).abs() < 0.0005 + 1e-9, "channel {number}: {} g", pga / G);
            assert!((t - t_max).abs() < 1e-9, "channel {number}: at {t} s");
            assert!(loaded.warnings.iter().any(|w| w.contains("Volume 1 record (uncorrected)")));
            assert!(!loaded.warnings.iter().any(|w| w.contains("holds 3 channels")), "a chosen channel: no warning");
            // the header's record length is n dt; the duration is first to last sample
            assert!((r.duration() - (n - 1) as f64 * 0.01).abs() < 1e-9);
        }
    }
    // no choice: the first, with a warning that names every channel and how to choose
    let loaded = load_record(&RecordSpec::new("CICLC.v1"), &cesmd()).unwrap();
    assert_eq!(loaded.channel.as_ref().unwrap().number, 1);
    let w = loaded.warnings.iter().find(|w| w.contains("holds 3 channels")).unwrap();
    for part in ["1 (90°), 2 (360°), 3 (vertical (Up))", "`channel = N` (`--channel N`)", "`--azimuth DEGREES`"] {
        assert!(w.contains(part), "{part}: {w}");
    }
}

#[test]
fn the_vertical_channel_is_refused_unless_asked_for() {
    let e = load_record(&spec("CICLC.v1", |s| s.channel = Some(3)), &cesmd()).unwrap_err().to_string();
    for part in [
        "field `allow_vertical`",
        "channel 3 of 3 (vertical (Up)) is a vertical component",
        "excitation is horizontal",
        "`channel = N`, `--channel N`",
        "`allow_vertical = true` (`--allow-vertical`)",
    ] {
        assert!(e.contains(part), "{part}: {e}");
    }
    let loaded = load_record(
        &spec("CICLC.v1", |s| {
            s.channel = Some(3);
            s.allow_vertical = true
        }),
        &cesmd(),
    )
    .unwrap();
    assert_eq!(loaded.record.acceleration.len(), 32190);
    assert!(loaded.warnings.iter().any(|w| w.contains("vertical component, read as asked")));
    // the 1979 Meloland overpass file, all capitals, its one channel UP
    let e = load_record(&RecordSpec::new("CE01336_CHAN01.V2"), &cesmd()).unwrap_err().to_string();
    assert!(e.contains("channel 1 of 1 (vertical (UP))") && !e.contains("`--channel N`"), "{e}");
}

#[test]
fn volume_2_files_modern_and_all_capitals() {
    // 7808 points at .010 s, cm/sec2; Peak acceleration = 13.616 cm/sec/sec at 18.200 sec
    let loaded = load_record(&RecordSpec::new("CE54730_CHAN001.V2"), &cesmd()).unwrap();
    assert_eq!(loaded.format, Format::Csmip);
    assert_eq!(loaded.channel.as_ref().unwrap().orientation, Orientation::Azimuth { degrees: 110.0 });
    let r = &loaded.record;
    assert_eq!((r.acceleration.len(), r.dt, r.units), (7808, 0.01, Units::CentimetersPerSecond2));
    let (pga, t) = peak(&r.acceleration, r.dt);
    assert!((pga * 100.0 - 13.616).abs() < 0.0005 && (t - 18.2).abs() < 1e-9, "{pga} at {t}");
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    assert_eq!(r.header.len(), 25, "the Volume 2 text header");
    // by azimuth too, and a wrong azimuth names what there is
    assert!(load_record(&spec("CE54730_CHAN001.V2", |s| s.azimuth = Some(110.0)), &cesmd()).is_ok());
    let e = load_record(&spec("CE54730_CHAN001.V2", |s| s.azimuth = Some(20.0)), &cesmd()).unwrap_err().to_string();
    assert!(e.contains("field `azimuth`: no channel of the file points at 20°; it holds 1 (110°)"), "{e}");
    // 1138 POINTS AT .020 SEC (no Fortran format: 8 fields of 10); PEAK
    // ACCELERATION = 171.589 CM/SEC/SEC AT 3.140 SEC
    let loaded = load_record(&spec("CE01336_CHAN01.V2", |s| s.allow_vertical = true), &cesmd()).unwrap();
    let r = &loaded.record;
    assert_eq!((r.acceleration.len(), r.dt, r.units), (1138, 0.02, Units::CentimetersPerSecond2));
    let (pga, t) = peak(&r.acceleration, r.dt);
    // the header says 3.140 s: sample 157 at 0.02 s
    assert!((pga * 100.0 - 171.589).abs() < 1e-9 && (t - 157.0 * 0.02).abs() < 1e-9, "{pga} at {t}");
    // the explicit format and its alias read the same
    for format in [Format::Csmip, serde_plain_format("dmg")] {
        let s = spec("CE54730_CHAN001.V2", |s| s.format = format);
        assert_eq!(load_record(&s, &cesmd()).unwrap().record.acceleration.len(), 7808);
    }
}

/// A format as a config names it.
fn serde_plain_format(name: &str) -> Format {
    #[derive(serde::Deserialize)]
    struct S {
        format: Format,
    }
    toml::from_str::<S>(&format!("format = \"{name}\"")).unwrap().format
}

#[test]
fn column_and_channel_refusals_say_what_to_use() {
    let e = load_record(&spec("CICLC.v1", |s| s.column = Some(2)), &cesmd()).unwrap_err().to_string();
    assert!(e.contains("field `column`") && e.contains("`channel = N` (`--channel N`)"), "{e}");
    let e = load_record(&spec("CICLC.v1", |s| s.channel = Some(4)), &cesmd()).unwrap_err().to_string();
    assert!(e.contains("the file has no channel 4; it holds 1 (90°), 2 (360°), 3 (vertical (Up))"), "{e}");
    let both = spec("CICLC.v1", |s| {
        s.channel = Some(1);
        s.azimuth = Some(90.0)
    });
    assert!(load_record(&both, &cesmd()).unwrap_err().to_string().contains("either `channel` or `azimuth`"));
    let text = spec("../RSN753_LOMAP_CLS090-hor2.AT2", |s| s.channel = Some(1));
    let e = load_record(&text, &cesmd()).unwrap_err().to_string();
    assert!(e.contains("field `channel`") && e.contains("read as PEER NGA AT2 holds one"), "{e}");
}

/// A COSMOS V2 channel: the test fixture with its station channel and
/// orientation set, its values scaled by `factor`.
fn cosmos_channel(number: u32, orientation: &str, factor: f64) -> String {
    let dir = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let text = std::fs::read_to_string(dir.join("CLS090.V2")).unwrap();
    let text = text.replace(
        "Sta Chan   1: 90 deg ( Rcrd Chan  1)",
        &format!("Sta Chan   {number}: {orientation} ( Rcrd Chan  {number})"),
    );
    assert!(text.contains(&format!("Sta Chan   {number}:")));
    if factor == 1.0 {
        return text;
    }
    // the data lines scaled (the header's peak then warns, which is fine here)
    let mut in_data = false;
    let mut out = String::new();
    for l in text.lines() {
        if l.contains("End-of-data") {
            in_data = false;
        }
        if in_data {
            // (8F10.5): fields of 10, touching where a value is below -100
            let fields = (0..l.len()).step_by(10).map(|a| l[a..(a + 10).min(l.len())].trim());
            out += &fields.map(|t| format!("{:10.5}", t.parse::<f64>().unwrap() * factor)).collect::<String>();
        } else {
            out += l;
        }
        out += "\n";
        in_data |= l.contains("acceleration pts");
    }
    out
}

#[test]
fn every_channel_of_a_multi_channel_cosmos_file() {
    let text = cosmos_channel(1, "90 deg", 1.0) + &cosmos_channel(2, "360 deg", 0.5) + &cosmos_channel(3, "Up", 0.25);
    let first = load_record_from_str(&RecordSpec::new("three.V2"), &text).unwrap();
    let pga = first.record.pga();
    assert!(first.warnings.iter().any(|w| w.contains("holds 3 channels, 1 (90°), 2 (360°), 3 (vertical (Up))")));
    for s in [spec("three.V2", |s| s.channel = Some(2)), spec("three.V2", |s| s.azimuth = Some(0.0))] {
        let loaded = load_record_from_str(&s, &text).unwrap();
        assert_eq!(loaded.channel.as_ref().unwrap().number, 2);
        assert!((loaded.record.pga() - 0.5 * pga).abs() < 1e-6 * pga, "channel 2 holds half the values");
    }
    let e = load_record_from_str(&spec("three.V2", |s| s.channel = Some(3)), &text).unwrap_err().to_string();
    assert!(e.contains("vertical"), "{e}");
    let e = load_record_from_str(&spec("three.V2", |s| s.column = Some(2)), &text).unwrap_err().to_string();
    assert!(e.contains("`channel = N` (`--channel N`)"), "{e}");
}

#[test]
fn a_huge_point_count_is_an_error_not_an_allocation() {
    let text = std::fs::read_to_string(cesmd().join("CE54730_CHAN001.V2")).unwrap();
    for count in ["2305843009213693951", "99999999999"] {
        let huge = text.replacen("  7808 points of accel data", &format!("{count} points of accel data"), 1);
        assert_ne!(huge, text);
        let e = load_record_from_str(&RecordSpec::new("huge.V2"), &huge).unwrap_err().to_string();
        assert!(e.contains(&format!("announces {count} points")), "{e}");
    }
    // a channel cut inside its headers
    let cut: String = text.lines().take(30).map(|l| format!("{l}\n")).collect();
    let e = load_record_from_str(&RecordSpec::new("cut.V2"), &cut).unwrap_err().to_string();
    assert!(e.contains("the channel ends inside the"), "{e}");
}

#[test]
fn velocity_and_displacement_sections_are_not_channels() {
    // a corrected COSMOS file may follow each channel's acceleration with
    // its velocity and displacement, each with a header of its own
    let acc = cosmos_channel(1, "90 deg", 1.0);
    let vel = acc.replace("Corrected acceleration", "Velocity data").replace("acceleration pts", "velocity pts");
    let dis =
        acc.replace("Corrected acceleration", "Displacement data").replace("acceleration pts", "displacement pts");
    let text = format!("{acc}{vel}{dis}");
    let loaded = load_record_from_str(&spec("one.V2", |s| s.azimuth = Some(90.0)), &text).unwrap();
    let c = loaded.channel.as_ref().unwrap();
    assert_eq!((c.number, c.of), (1, 1), "one channel, not three");
    assert!(!loaded.warnings.iter().any(|w| w.contains("channels")), "{:?}", loaded.warnings);
}
