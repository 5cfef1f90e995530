//! The verification manual: every reference problem
//! (`quakejoint_model::verification::PROBLEMS`) within its acceptance band
//! against its independent solution, and `docs/verification.md` listing
//! each with the result this code gives. `QJ_UPDATE_DOCS=1 cargo test -p
//! quakejoint-model --test verification` rewrites the manual's table.

use std::path::PathBuf;

use quakejoint_model::verification::{manual_table, PROBLEMS};

#[test]
fn every_reference_problem_is_within_its_band_and_the_manual_is_current() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let outcomes: Vec<_> = PROBLEMS.iter().map(|p| (p.run)(&root)).collect();
    let mut failures = Vec::new();
    for (p, o) in PROBLEMS.iter().zip(&outcomes) {
        match o {
            Ok(o) => {
                let error = p.band.error(o.computed, o.reference);
                eprintln!("{}: computed {:e}, reference {:e}, error {error:.2e}", p.id, o.computed, o.reference);
                if error.is_nan() || error > p.band.limit() {
                    failures.push(format!("{}: error {error:e} beyond {}", p.id, p.band.describe()));
                }
            }
            Err(e) => failures.push(format!("{}: {e}", p.id)),
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
    let path = root.join("docs/verification.md");
    let text = std::fs::read_to_string(&path).expect("docs/verification.md");
    let marker = "<!-- generated from crates/model/src/verification: table -->\n";
    let start = text.find(marker).expect("the table's marker") + marker.len();
    let end = start + text[start..].find("<!-- end -->").expect("the end marker");
    let table = manual_table(&outcomes);
    if std::env::var_os("QJ_UPDATE_DOCS").is_some() {
        std::fs::write(&path, format!("{}{table}{}", &text[..start], &text[end..])).unwrap();
        return;
    }
    assert_eq!(&text[start..end], table, "docs/verification.md is not current: QJ_UPDATE_DOCS=1");
}
