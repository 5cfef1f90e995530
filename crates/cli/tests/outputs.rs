//! Self-describing outputs: every HDF5 file says what produced it and what
//! its numbers mean, and `docs/hdf5-layout.md` matches the files.
//!
//! - Provenance: the command, the config file as read, the config as used
//!   after command-line overrides (`simulate --record/--period`, `service
//!   --speed/--amplitude/--cycles`), and every record file with its SHA-256.
//! - Units: every numeric dataset has a `units` attribute; no attribute holds
//!   a floating-point number (numbers with units are datasets); integer
//!   attributes are counts.
//! - NaN for what a run did not compute (the joint's quantities and the
//!   solver counters of the exact solution without the joint).
//! - The sweep's result arrays carry HDF5 dimension scales (case, record,
//!   damping, period; a bridge given by its modes: period scale), read
//!   back by h5py.
//! - Every dataset and group of the files is in `docs/hdf5-layout.md`, and
//!   every path the document lists exists in a file.

mod common;

use std::collections::BTreeSet;
use std::path::Path;

use common::{config, dir, ok, root, run};

fn attr_string(loc: &hdf5::Location, name: &str) -> String {
    quakejoint_io::h5::read_attr_str(loc, name).unwrap_or_else(|e| panic!("attribute {name}: {e}"))
}

/// Every object path of a file (groups and datasets), and checks on the
/// way: numeric datasets have units, attributes hold no floats.
fn walk(group: &hdf5::Group, prefix: &str, paths: &mut BTreeSet<String>) {
    for attr in group.attr_names().unwrap() {
        let dtype = group.attr(&attr).unwrap().dtype().unwrap();
        assert!(!dtype.is::<f64>() && !dtype.is::<f32>(), "{prefix}: attribute {attr} holds a float without units");
    }
    for name in group.member_names().unwrap() {
        let path = format!("{prefix}/{name}");
        if let Ok(g) = group.group(&name) {
            paths.insert(path.clone());
            walk(&g, &path, paths);
        } else {
            let ds = group.dataset(&name).unwrap();
            let dtype = ds.dtype().unwrap();
            if dtype.is::<f64>() {
                assert!(ds.attr("units").is_ok(), "{path}: a numeric dataset without units");
            }
            for attr in ds.attr_names().unwrap() {
                let t = ds.attr(&attr).unwrap().dtype().unwrap();
                assert!(!t.is::<f64>(), "{path}: attribute {attr} holds a float");
            }
            paths.insert(path);
        }
    }
}

fn paths_of(file: &Path) -> BTreeSet<String> {
    let f = hdf5::File::open(file).unwrap();
    let mut paths = BTreeSet::new();
    walk(&f, "", &mut paths);
    paths
}

/// Paths listed in docs/hdf5-layout.md (in backquotes, starting with `/`),
/// with `<...>` placeholders.
fn documented_paths() -> Vec<String> {
    let doc = std::fs::read_to_string(root().join("docs/hdf5-layout.md")).unwrap();
    let mut out = Vec::new();
    for part in doc.split('`').skip(1).step_by(2) {
        if part.starts_with('/') && !part.contains(' ') {
            out.push(part.to_string());
        }
    }
    out
}

/// Whether a concrete path matches a documented one: `<...>` matches one
/// path component; `{a,b}` any of the names.
fn matches(doc: &str, path: &str) -> bool {
    let (d, p): (Vec<&str>, Vec<&str>) = (doc.split('/').collect(), path.split('/').collect());
    d.len() == p.len()
        && d.iter().zip(&p).all(|(d, p)| {
            if d.starts_with('<') || d.ends_with('>') || d.contains("<") {
                let prefix = d.split('<').next().unwrap_or("");
                p.starts_with(prefix)
            } else if d.starts_with('{') {
                d.trim_matches(|c| c == '{' || c == '}').split(',').any(|n| n == *p)
            } else {
                d == p
            }
        })
}

#[test]
fn every_file_says_what_produced_it_and_carries_units() {
    let d = dir("outputs");
    let cfg = config(&d, "c.toml", "[sweep]\nperiods = [0.5, 1.0]\ndamping = [0.02, 0.05]\nhistories = [1.0]\n", 2.0);
    let text = std::fs::read_to_string(&cfg).unwrap();
    let other = root().join("ground_motions/RSN77_SFERN_PUL164-hor1.AT2");

    // simulate with a record and a period from the command line
    let run_h5 = d.join("run.h5");
    let res = run(&[
        "simulate",
        cfg.to_str().unwrap(),
        "--record",
        other.to_str().unwrap(),
        "--period",
        "1.5",
        "--output",
        run_h5.to_str().unwrap(),
        "--json",
    ]);
    assert!(matches!(res.status.code(), Some(0 | 4)), "{}", String::from_utf8_lossy(&res.stderr));
    let f = hdf5::File::open(&run_h5).unwrap();
    assert_eq!(attr_string(&f, "config_file"), text, "the config as read");
    let used: toml::Table = toml::from_str(&attr_string(&f, "config")).unwrap();
    assert!(used["record"]["file"].as_str().unwrap().ends_with("RSN77_SFERN_PUL164-hor1.AT2"), "{used:?}");
    assert_eq!(used["bridge"]["period"].as_float(), Some(1.5));
    assert!(attr_string(&f, "command").contains("--period 1.5"));
    let x = f.group("inputs/records/x").unwrap();
    let sha = quakejoint_motion::sha256_hex(&std::fs::read(&other).unwrap());
    assert_eq!(attr_string(&x, "sha256"), sha);
    assert_eq!(attr_string(&x, "file_units"), "g");
    assert_eq!(f.dataset("result/period").unwrap().read_scalar::<f64>().unwrap(), 1.5);
    assert_eq!(attr_string(&f.dataset("result/sa").unwrap(), "units"), "m/s^2");
    assert_eq!(attr_string(&f.dataset("result/max_angle_residual").unwrap(), "units"), "rad");
    let mut all = paths_of(&run_h5);

    // without the joint: what was not computed is NaN
    let exact = d.join("exact.h5");
    ok(&run(&["simulate", cfg.to_str().unwrap(), "--no-joint", "--output", exact.to_str().unwrap()]));
    let f = hdf5::File::open(&exact).unwrap();
    for name in ["peak_joint_force", "friction_energy", "energy_error", "steps", "newton_iterations"] {
        let v: f64 = f.dataset(&format!("result/{name}")).unwrap().read_scalar().unwrap();
        assert!(v.is_nan(), "{name} = {v} without the joint");
    }
    assert!(f.dataset("result/sa").unwrap().read_scalar::<f64>().unwrap() > 0.0);
    assert_eq!(attr_string(&f, "method"), "exact linear, without the joint");
    all.extend(paths_of(&exact));

    // the deck across the bridge under a transverse record
    let across = config(
        &d,
        "across.toml",
        &format!(
            "[bridge]\ntransverse_period = 1.0\n[record_y]\nfile = {:?}\nscale = 0.15\n",
            root().join("ground_motions/RSN753_LOMAP_CLS000-hor1.AT2")
        ),
        2.0,
    );
    let across_h5 = d.join("across.h5");
    let res = run(&["simulate", across.to_str().unwrap(), "--output", across_h5.to_str().unwrap()]);
    assert!(matches!(res.status.code(), Some(0 | 4)), "{}", String::from_utf8_lossy(&res.stderr));
    let f = hdf5::File::open(&across_h5).unwrap();
    assert!(f.dataset("result/sa_y").unwrap().read_scalar::<f64>().unwrap() > 0.0);
    all.extend(paths_of(&across_h5));

    // a suite of two records scaled to a target spectrum, with its statistics
    let records = ["RSN753_LOMAP_CLS090-hor2.AT2", "RSN6_IMPVALL.I_I-ELC180-hor1.AT2"]
        .map(|r| format!("{{ file = {:?} }}", root().join("ground_motions").join(r)));
    let suite = config(
        &d,
        "suite.toml",
        &format!(
            "[sweep]\nperiods = [0.5]\nrecords = [{}]\n[sweep.suite]\ntarget = {{ code = \"asce7\", sds_g = 0.2, \
             sd1_g = 0.1, tl = 8.0 }}\n",
            records.join(", ")
        ),
        // the records are fitted over the window: a 1 s window of El Centro
        // is nearly at rest and would need a factor of 80
        6.0,
    );
    let suite_h5 = d.join("suite.h5");
    let res = run(&["sweep", suite.to_str().unwrap(), "--output", suite_h5.to_str().unwrap()]);
    assert!(matches!(res.status.code(), Some(0 | 4)), "{}", String::from_utf8_lossy(&res.stderr));
    all.extend(paths_of(&suite_h5));

    // stripes of Sa with a hazard curve and a target: /fragility and
    // /fragility/design
    let stripes = config(
        &d,
        "stripes.toml",
        &format!(
            "[sweep]\nperiods = [0.5]\nrecords = [{}]\n[sweep.stripes]\nmeasure = \"sa\"\nlevels = [0.05, 0.1]\n\
             [sweep.fragility]\nbootstrap = 10\nhazard = {{ intensity = [0.1, 1.0], frequency = [1e-2, 1e-4] }}\n\
             [[sweep.fragility.limit_states]]\nkind = \"capacity\"\ntarget = 1e-3\n\
             [[sweep.fragility.limit_states]]\nkind = \"pounding\"\n",
            records.join(", ")
        ),
        2.0,
    );
    let stripes_h5 = d.join("stripes.h5");
    let res = run(&["sweep", stripes.to_str().unwrap(), "--output", stripes_h5.to_str().unwrap()]);
    assert!(matches!(res.status.code(), Some(0 | 4)), "{}", String::from_utf8_lossy(&res.stderr));
    all.extend(paths_of(&stripes_h5));

    // service with options from the command line
    let loop_h5 = d.join("loop.h5");
    let medium = root().join("configs/medium.toml");
    ok(&run(&[
        "service",
        medium.to_str().unwrap(),
        "--speed",
        "0.1",
        "--amplitude",
        "0.05",
        "--cycles",
        "3",
        "--output",
        loop_h5.to_str().unwrap(),
    ]));
    let f = hdf5::File::open(&loop_h5).unwrap();
    let used: toml::Table = toml::from_str(&attr_string(&f, "config")).unwrap();
    assert_eq!(used["service"]["speed"].as_float(), Some(0.1));
    assert_eq!(used["service"]["amplitude"].as_float(), Some(0.05));
    assert_eq!(used["service"]["cycles"].as_integer(), Some(3));
    assert_eq!(f.dataset("service/center_beam_dx").unwrap().shape()[0], 9);
    all.extend(paths_of(&loop_h5));

    // a sweep, its arrays naming their axes in a checksummed attribute
    // (no dimension scale: their references live in the global heap)
    let sweep_h5 = d.join("sweep.h5");
    ok(&run(&["sweep", cfg.to_str().unwrap(), "--output", sweep_h5.to_str().unwrap()]));
    all.extend(paths_of(&sweep_h5));
    if common::python_with(&["h5py"]) {
        let h5py = std::process::Command::new("python3")
            .arg("-c")
            .arg(
                "import sys, h5py\n\
                 f = h5py.File(sys.argv[1], 'r')\n\
                 for name in ['spectrum/with_joint/sa', 'spectrum/with_joint/status', 'spectrum/reduction']:\n\
                 \x20   ds = f[name]\n\
                 \x20   assert ds.attrs['dims'].decode().split(', ') == ['case', 'record', 'damping', 'period']\n\
                 \x20   assert 'DIMENSION_LIST' not in ds.attrs\n\
                 ds = f['spectrum/without_joint/sa']\n\
                 assert ds.attrs['dims'].decode() == 'record, damping, period'\n\
                 assert list(f['spectrum/period'][:]) == [0.5, 1.0]\n\
                 print('ok')",
            )
            .arg(&sweep_h5)
            .output()
            .unwrap();
        assert!(h5py.status.success(), "h5py: {}", String::from_utf8_lossy(&h5py.stderr));
    }

    // a bridge given by its modes with two joints: a run (its points and
    // its second joint) and a sweep over period scales
    let modal = config(
        &d,
        "modal.toml",
        &format!(
            "[bridge.modal]\nmodes = {:?}\nmodes_used = 20\n\
             [[joints]]\nname = \"left\"\ndeck_point = \"left end\"\ndeck_side = \"+x\"\n\
             [[joints]]\nname = \"right\"\ndeck_point = \"right end\"\ndeck_side = \"-x\"\n\
             [sweep]\nperiod_scales = [0.8, 1.0]\nhistories = [1.0]\n",
            root().join("tests/data/three_span/modes.toml")
        ),
        2.0,
    );
    let modal_run = d.join("modal_run.h5");
    ok(&run(&["simulate", modal.to_str().unwrap(), "--output", modal_run.to_str().unwrap()]));
    all.extend(paths_of(&modal_run));
    let modal_sweep = d.join("modal_sweep.h5");
    ok(&run(&["sweep", modal.to_str().unwrap(), "--output", modal_sweep.to_str().unwrap()]));
    let f = hdf5::File::open(&modal_sweep).unwrap();
    assert!(!f.link_exists("spectrum/period"), "the period scales are not periods");
    assert_eq!(attr_string(&f.group("joints/1").unwrap(), "name"), "right");
    all.extend(paths_of(&modal_sweep));
    if common::python_with(&["h5py"]) {
        let h5py = std::process::Command::new("python3")
            .arg("-c")
            .arg(
                "import sys, h5py\n\
                 f = h5py.File(sys.argv[1], 'r')\n\
                 for name in ['spectrum/with_joint/sa', 'spectrum/without_joint/sa', 'joints/1/max_subgap']:\n\
                 \x20   assert f[name].attrs['dims'].decode() == 'case, record, damping, period_scale'\n\
                 assert 'period_scale' in f['spectrum']\n\
                 print('ok')",
            )
            .arg(&modal_sweep)
            .output()
            .unwrap();
        assert!(h5py.status.success(), "h5py: {}", String::from_utf8_lossy(&h5py.stderr));
    }

    // a sparsity file
    let sparsity = d.join("sparsity.h5");
    ok(&run(&["model", medium.to_str().unwrap(), "--sparsity", sparsity.to_str().unwrap()]));
    all.extend(paths_of(&sparsity));

    assert!(all.len() > 100, "{} paths in the files", all.len());
    // the layout document and the files agree
    let documented = documented_paths();
    let undocumented: Vec<&String> = all.iter().filter(|p| !documented.iter().any(|d| matches(d, p))).collect();
    assert!(undocumented.is_empty(), "not in docs/hdf5-layout.md: {undocumented:?}");
    let missing: Vec<&String> = documented.iter().filter(|d| !all.iter().any(|p| matches(d, p))).collect();
    assert!(missing.is_empty(), "documented but in no file: {missing:?}");
}
