//! The lists of results in `docs/hdf5-layout.md` are made from the one list
//! in the code (`quakejoint_model::fields::FIELDS`): a run file's `/result`
//! table and a sweep's per-job fields; its `/history` table from the list of
//! the histories' series and tables (`quakejoint_model::history`), its
//! `/joints` and `/points` tables from the lists of a joint's and a point's
//! values (`quakejoint_model::run::JOINT_FIELDS`, `modal::POINT_FIELDS`). This test fails when they differ;
//! `QJ_UPDATE_DOCS=1 cargo test -p quakejoint-model --test fields_doc`
//! rewrites them.

use quakejoint_model::fields::markdown_tables;

/// `text` with the block after the marker `<!-- generated from ...: name -->`
/// (up to `<!-- end -->`) replaced by `body`, and the block found there.
fn replace_block(text: &str, name: &str, body: &str) -> (String, String) {
    let source = if name == "history" { "history.rs" } else { "fields.rs" };
    let marker = format!("<!-- generated from crates/model/src/{source}: {name} -->\n");
    let start = text.find(&marker).unwrap_or_else(|| panic!("no marker `{marker}` in the doc")) + marker.len();
    let end = start + text[start..].find("<!-- end -->").expect("an end marker");
    (format!("{}{body}{}", &text[..start], &text[end..]), text[start..end].to_string())
}

#[test]
fn the_docs_list_every_result_as_the_code_does() {
    let path = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../docs/hdf5-layout.md");
    let text = std::fs::read_to_string(&path).unwrap();
    let (result, per_job) = markdown_tables();
    let (text2, old_result) = replace_block(&text, "result", &result);
    let (text3, old_per_job) = replace_block(&text2, "per_job", &per_job);
    let history = quakejoint_model::history::markdown_table();
    let (text4, old_history) = replace_block(&text3, "history", &history);
    let (joints, points) = quakejoint_model::fields::joint_and_point_tables();
    let (text5, old_joints) = replace_block(&text4, "joints", &joints);
    let (text6, old_points) = replace_block(&text5, "points", &points);
    if std::env::var_os("QJ_UPDATE_DOCS").is_some() {
        std::fs::write(&path, text6).unwrap();
        return;
    }
    assert_eq!(old_joints, joints, "docs/hdf5-layout.md's /joints table is not the code's: QJ_UPDATE_DOCS=1");
    assert_eq!(old_points, points, "docs/hdf5-layout.md's /points table is not the code's: QJ_UPDATE_DOCS=1");
    assert_eq!(old_history, history, "docs/hdf5-layout.md's /history table is not the code's: QJ_UPDATE_DOCS=1");
    assert_eq!(old_result, result, "docs/hdf5-layout.md's /result table is not the code's: QJ_UPDATE_DOCS=1");
    assert_eq!(old_per_job, per_job, "docs/hdf5-layout.md's per-job fields are not the code's: QJ_UPDATE_DOCS=1");
}
