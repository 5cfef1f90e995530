//! A named quantity of the results, with its units and meaning
//! ([`Described`]): the lists of a joint's and a point's values are made
//! of them, and the outputs and `docs/hdf5-layout.md` take their names,
//! units and meanings from those lists.

/// A result's name in every output, its units and what it is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Described {
    /// Its name.
    pub name: &'static str,
    /// Its units.
    pub units: &'static str,
    /// What it is (a line of `docs/hdf5-layout.md`).
    pub meaning: &'static str,
}

/// A described quantity.
pub const fn described(name: &'static str, units: &'static str, meaning: &'static str) -> Described {
    Described { name, units, meaning }
}
