//! Signal processing shared by the run pipeline, the reports, validation and the
//! studies: Butterworth low-pass filters, the acquisition chain built on them, dominant
//! frequencies of an amplitude spectrum, Welch power spectral densities. Plain functions on sampled data; nothing here knows
//! runs, scenes or files.

pub mod acquisition;
pub mod butterworth;
pub mod psd;
pub mod spectrum;
