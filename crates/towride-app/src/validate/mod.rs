//! Validation against recorded accelerometer data.
//!
//! A measured run is a CSV of time plus channels and a TOML descriptor ([`descriptor`]).
//! [`validate_run`] reads both ([`csv_reader`], [`timebase`], [`measurement`]: any
//! logger's layout, units, time bases, clipped samples), takes the true speed from the
//! foil pulses ([`trigger`]), a speed channel or the descriptor ([`speed`]), finds the
//! obstacle passage in the signals when there is no trigger ([`passage`]), asks a
//! [`Simulator`] for the run at that speed, passes the simulation through the
//! acquisition chain ([`filter`]), aligns it in time from the events refined by a bounded
//! cross-correlation ([`align`]), and scores every channel ([`metrics`], [`rating`],
//! [`compare`]) — once with these corrections and once without (nominal speed, event
//! timing only), so the effect of the corrections is visible. [`spectrum`] gives each
//! channel's body-bounce and wheel-hop frequencies, [`folder`] the summary of a folder
//! and [`trends`] its trends (peaks against speed, frequencies measured and simulated).
//! [`init`] drafts a descriptor from a recording and a scene (`validate init`).
//!
//! The vehicle simulation enters only through the [`Simulator`] trait; the command line
//! takes its simulator from [`default_simulator`], the one place to swap in the vehicle
//! model. [`synth`] and [`plan`] make clearly labelled synthetic runs from any simulator.

pub(crate) mod align;
pub mod compare;
pub mod csv_reader;
pub mod descriptor;
pub mod filter;
pub mod folder;
pub mod html;
pub mod init;
pub mod mdf;
pub mod measurement;
pub(crate) mod metrics;
pub mod passage;
pub mod pipeline;
pub mod plan;
pub mod rating;
mod repair;
pub mod report;
pub mod scene_info;
mod text;

pub mod geometry;
pub mod offsets;
pub mod spectra;
pub mod speed;
pub mod synth;
pub mod timebase;
pub mod trends;
pub(crate) mod trends_svg;
pub(crate) mod trigger;
pub mod units;
pub(crate) mod vehicle_sim;

use std::collections::BTreeMap;
use std::path::Path;

pub use crate::error::ValidateError;
pub use descriptor::Descriptor;
pub use folder::{validate_folder, write_summary, FolderResult};
pub use pipeline::{validate_run, Comparison, Options, RunValidation};

/// Standard gravity [m/s^2], for channels recorded in g.
pub const G_MPS2: f64 = 9.80665;

/// A simulated run: sampled channels in SI units on one time grid.
#[derive(Clone, Debug, Default)]
pub struct SimChannels {
    /// Sample times [s], increasing.
    pub time_s: Vec<f64>,
    /// Channel name (e.g. `acc_trailer_drawbar_z`) -> values in SI units [m/s^2].
    pub channels: BTreeMap<String, Vec<f64>>,
    /// When the front wheels reach the obstacle start [s], on the same clock as `time_s`.
    pub obstacle_time_s: f64,
}

/// Anything that can simulate a measured run: the vehicle model, or a stand-in.
pub trait Simulator {
    /// Simulates `scene` driven at `speed_mps` with trailer load case `load_case` (a
    /// load case of the scene's trailer file).
    fn simulate(
        &self,
        scene: &Path,
        speed_mps: f64,
        load_case: &str,
    ) -> Result<SimChannels, crate::Error>;

    /// A short name for reports and synthetic-data labels.
    fn name(&self) -> String {
        "unnamed simulator".into()
    }

    /// Distances behind the front axle of the rear axle and of a trailer's axle [m], when
    /// the simulator knows the vehicle of `scene` (the passage search expects the axles
    /// there).
    fn axles(&self, _scene: &Path) -> (Option<f64>, Option<f64>) {
        (None, None)
    }

    /// The obstacle geometry `scene` assumes, as this simulator reads it.
    fn obstacle_geometry(&self, scene: &Path) -> Option<geometry::ObstacleGeometry> {
        geometry::of_scene(scene, &towride_mbs::input::Loader::new())
    }
}

/// The simulator the command line uses: the vehicle model driven through a scene file
/// (the analytic stand-in of [`standin`] remains for tests of the pipeline itself).
pub fn default_simulator() -> Box<dyn Simulator> {
    Box::new(vehicle_sim::VehicleSimulator::default())
}

/// The vehicle model reading its files through `loader` (the command line's overrides).
pub fn simulator_with(loader: towride_mbs::input::Loader) -> Box<dyn Simulator> {
    Box::new(vehicle_sim::VehicleSimulator { loader })
}
