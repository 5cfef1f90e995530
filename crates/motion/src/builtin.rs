//! The record built into the program: the default of every config without
//! a `[record]` (the model description's default), Loma Prieta 1989,
//! Corralitos, component 090 (PEER NGA-West2 RSN753, file
//! `RSN753_LOMAP_CLS090-hor2.AT2`, byte for byte as in `ground_motions/`,
//! whose `PROVENANCE.md` gives its source and SHA-256). A config names it
//! `file = "builtin:RSN753_LOMAP_CLS090-hor2.AT2"`.

use std::path::Path;

/// The prefix of built-in record names.
pub const PREFIX: &str = "builtin:";

/// The default record's file name (with [`PREFIX`]).
pub const DEFAULT: &str = "builtin:RSN753_LOMAP_CLS090-hor2.AT2";

const CORRALITOS_090: &[u8] = include_bytes!("../../../ground_motions/RSN753_LOMAP_CLS090-hor2.AT2");

/// The bytes of a built-in record named by `file`, if it names one.
pub fn bytes(file: &Path) -> Option<&'static [u8]> {
    (file.to_str()? == DEFAULT).then_some(CORRALITOS_090)
}

/// Whether `file` uses the built-in prefix (a built-in record, or a typo
/// in one).
pub fn is_builtin(file: &Path) -> bool {
    file.to_str().is_some_and(|f| f.starts_with(PREFIX))
}
