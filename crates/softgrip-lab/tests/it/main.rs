//! The integration tests, one binary: one module per subject.

mod beam;
mod cancel;
mod compare;
mod diagnose;
mod diagnose_run;
mod discretisation;
mod fit;
mod fit_many;
mod grasp;
mod grasp_window;
mod modulus;
mod no_equilibrium;
mod plot;
mod prove;
mod recordings;
mod regions;
mod remainder;
mod replay;
mod schema;
mod sensitivity;
mod support;
mod sweep;
mod synth;
mod table;
