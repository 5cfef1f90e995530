//! The link element as a joint of a run (`joint.model = "link"`).
//!
//! - Its energy balance closes: the slider's friction, the closed joint's
//!   contact and the deck's damping against the earthquake's work.
//! - A joint of 3 center beams at a pitch of 0.1 m (cells of 10 mm, 40 mm to
//!   close) on a deck that moves 137 mm: the link closes (impacts, a force
//!   of the closed joint on the deck) and its cells open beyond a capacity
//!   of 30 mm (`capacity_exceeded`), as the detailed joint reports them; at
//!   the reference pitch (cells of 40 mm, capacity 80 mm) neither.
//! - Without `[joint.link]` the config is refused, naming the table.

use std::path::PathBuf;

use quakejoint_model::run::{load_records, simulate_records, RunOptions};
use quakejoint_model::Config;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

const LINK: &str =
    "[joint.link]\nstiffness = 5e6\nfriction = 9e3\nmass = 800.0\ngap_stiffness = 1e8\ngap_hertz = 5e9\n";

fn run(pitch: f64, capacity: f64) -> quakejoint_model::run::RunResult {
    let text = format!(
        "[joint]\nmodel = \"link\"\ncenter_beams = 3\npitch = {pitch}\n[joint.capacity]\nmax_subgap = {capacity}\n{LINK}\
         [bridge]\nmass = 1e6\nperiod = 1.0\n[record]\nfile = \"{}\"\n",
        root().join("ground_motions/RSN753_LOMAP_CLS090-hor2.AT2").display()
    );
    let config = Config::from_toml(&text, "link.toml").unwrap();
    let (x, _) = load_records(&config, &root()).unwrap();
    simulate_records(&config, &x.record, None, &RunOptions::default()).unwrap()
}

#[test]
fn a_link_closes_its_energy_balance_closes_and_reports_its_cells() {
    let open = run(0.13, 0.08);
    eprintln!(
        "open: friction {:.1} kJ, energy balance {:.1e}, cells {:.1} .. {:.1} mm, peak force {:.1} kN",
        open.friction_energy / 1e3,
        open.energy_error,
        open.min_subgap.unwrap() * 1e3,
        open.max_subgap.unwrap() * 1e3,
        open.peak_joint_force / 1e3
    );
    assert!(open.energy_error < 1e-5, "{}", open.energy_error);
    assert!(open.friction_energy > 0.0 && open.pounding.impacts == 0);
    // cells of 40 mm at rest, opening alike by u / 4
    let (lo, hi) = (open.min_subgap.unwrap(), open.max_subgap.unwrap());
    assert!(lo < 0.04 && hi > 0.04 && (hi - 0.04) < open.sd / 4.0 + 1e-9);
    assert!(open.validity.flags.is_ok(), "{:?}", open.validity);

    let tight = run(0.1, 0.03);
    eprintln!(
        "tight: closures {}, peak closed-joint force {:.1} kN at {:.3} s, energy balance {:.1e}, {:?}",
        tight.pounding.impacts,
        tight.pounding.peak_deck_contact_force / 1e3,
        tight.pounding.peak_contact_time,
        tight.energy_error,
        tight.validity.findings
    );
    assert!(tight.pounding.impacts > 0 && tight.pounding.peak_deck_contact_force > 0.0);
    assert!(tight.pounding.contact_energy >= 0.0 && tight.energy_error < 1e-5, "{}", tight.energy_error);
    assert!(tight.validity.flags.0 & quakejoint_model::validity::Flags::CAPACITY_EXCEEDED.0 != 0);
    assert!(tight.validity.findings.iter().any(|f| f.contains("link")));
}

#[test]
fn a_link_without_its_table_is_refused() {
    let e = Config::from_toml("[joint]\nmodel = \"link\"\n", "link.toml").unwrap_err().to_string();
    assert!(e.contains("joint.link") && e.contains("quakejoint calibrate"), "{e}");
}
