//! The integration tests, one module per concern, linked into one test
//! binary (one link of the crate instead of one per file).
//!
//! `cargo test --release` runs the fast tier; `-- --include-ignored` adds the
//! slow tier. `mpi` and `replay` build only with their features:
//! `cargo test --release --features mpi --test suite mpi::`.

mod common;

mod bodies;
mod broad_phase;
mod check;
mod cli;
mod contact_dynamics;
mod contact_geometry;
mod contact_memory;
mod contact_oracle;
mod contact_ties;
mod damping;
mod defaults;
mod first_hour;
mod free_flight;
mod friction;
mod friction_energy;
mod guards;
mod habits;
mod integrity;
mod loader_fuzz;
mod messages;
#[cfg(feature = "mpi")]
mod mpi;
mod plot;
mod reference;
mod render;
#[cfg(feature = "replay")]
mod replay;
mod resume;
mod rotator_order;
mod rotators;
mod scenario_reference;
mod settle;
mod spheres;
mod stress;
mod study;
mod summary_resume;
mod threads;
mod trajectory;
mod units_doc;
mod vtk;
