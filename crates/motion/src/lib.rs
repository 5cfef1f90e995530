//! Ground-motion records and exact linear response spectra (to be written).
