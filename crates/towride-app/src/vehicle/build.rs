//! The templates' side of the model builder: [`ModelBuilder`] calls in the terms the
//! property files use (mass properties, bushing laws), with the loader that reads the
//! property files. Every check is the model builder's; a refusal here is reported
//! against the property file being translated.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::props::{BushingLaws, Mass};
use towride_mbs::flex::feedback::RunModes;
use towride_mbs::input::{InputError, Loader, Source};
pub use towride_mbs::model::builder::Link;
use towride_mbs::model::builder::{
    Axes, BodyDesc, BodyHandle, BushingLine, ElementHandle, ModelBuilder, Placement, RotLine, V,
};
use towride_mbs::model::desc::{Law, Model};
use towride_mbs::model::ModelError;

/// A model builder with the loader of the property files and the file being read.
pub struct Builder {
    /// The model builder.
    pub mb: ModelBuilder,
    /// Reads the templates' property files with the run's overrides.
    pub loader: Loader,
    /// Modes of the modal bodies chosen from an earlier run, if any ([`super::Options`]).
    pub run_modes: Option<Arc<RunModes>>,
    /// The property file being translated (for builder refusals).
    file: PathBuf,
}

impl Builder {
    /// A builder for a new vehicle model.
    pub fn new(mb: ModelBuilder, loader: &Loader, run_modes: Option<Arc<RunModes>>) -> Builder {
        Builder {
            mb,
            loader: loader.clone(),
            run_modes,
            file: PathBuf::new(),
        }
    }

    /// Reads a property file (through the loader); later refusals name it.
    pub fn read(&mut self, file: &Path) -> Result<Source, InputError> {
        self.file = file.to_path_buf();
        self.loader.toml(file)
    }

    /// A builder refusal as an error of the property file being translated.
    pub fn refused(&self, e: ModelError) -> InputError {
        let (field, message) = match e {
            ModelError::Build { item, error } => {
                let f = towride_mbs::input::path_string(&error.field);
                (
                    if f.is_empty() {
                        item
                    } else {
                        format!("{item}: {f}")
                    },
                    error.message,
                )
            }
            other => (String::new(), other.to_string()),
        };
        InputError {
            file: self.file.clone(),
            line: None,
            column: None,
            field,
            message,
            kind: Default::default(),
        }
    }

    /// The model so far.
    pub fn model(&self) -> &Model {
        self.mb.model()
    }

    /// The model so far, for changes the builder does not make.
    pub fn model_mut(&mut self) -> &mut Model {
        self.mb.model_mut()
    }

    /// Where the coordinates handed to the builder lie in the world from now on.
    pub fn set_place(&mut self, p: Placement) {
        self.mb.set_place(p);
    }

    /// A rigid body with axes along the subsystem's, and its marker `<name>.cm`.
    pub fn body(&mut self, name: &str, m: &Mass) -> Result<BodyHandle, InputError> {
        let d = BodyDesc {
            name: name.into(),
            mass: m.mass,
            inertia: m.inertia,
            cm: m.cm,
            axes: towride_mbs::model::builder::IDENTITY,
            velocity: [0.0; 3],
            angular_velocity: [0.0; 3],
        };
        self.mb.body(d).map_err(|e| self.refused(e))
    }

    /// One model-builder call, its refusal reported against the property file being
    /// translated: `b.add(|m| m.joint(...))?`.
    pub fn add<T>(
        &mut self,
        f: impl FnOnce(&mut ModelBuilder) -> Result<T, ModelError>,
    ) -> Result<T, InputError> {
        f(&mut self.mb).map_err(|e| self.refused(e))
    }

    /// A rubber bushing at `p`; `axes` are the bushing's (subsystem coordinates).
    #[allow(clippy::too_many_arguments)]
    pub fn bushing(
        &mut self,
        name: &str,
        bi: Option<BodyHandle>,
        bj: Option<BodyHandle>,
        p: V,
        axes: &Axes,
        laws: &BushingLaws,
        preload: [f64; 6],
    ) -> Result<ElementHandle, InputError> {
        self.mb
            .bushing(bushing_line(name, bi, bj, p, axes, laws, preload))
            .map_err(|e| self.refused(e))
    }

    /// A bushing without preload linking two bodies as a joint would (a mount that is a
    /// bushing or a fixed joint), as the [`Link`] to pin to a modal node.
    pub fn bushing_link(
        &mut self,
        name: &str,
        bi: Option<BodyHandle>,
        bj: Option<BodyHandle>,
        p: V,
        axes: &Axes,
        laws: &BushingLaws,
    ) -> Result<Link, InputError> {
        self.mb
            .bushing_link(bushing_line(name, bi, bj, p, axes, laws, [0.0; 6]))
            .map_err(|e| self.refused(e))
    }

    /// A torsion spring-damper about the z axis of `axes` at `p`.
    #[allow(clippy::too_many_arguments)]
    pub fn torsion(
        &mut self,
        name: &str,
        bi: Option<BodyHandle>,
        bj: Option<BodyHandle>,
        p: V,
        axes: &Axes,
        spring: Law,
        damper: Law,
    ) -> Result<ElementHandle, InputError> {
        self.mb
            .rot_spring(RotLine {
                name: name.into(),
                body_i: bi,
                body_j: bj,
                point: p,
                axes: *axes,
                free_angle: 0.0,
                preload: 0.0,
                spring,
                damper,
            })
            .map_err(|e| self.refused(e))
    }
}

/// The bushing a template asks for, in the model builder's terms.
fn bushing_line(
    name: &str,
    bi: Option<BodyHandle>,
    bj: Option<BodyHandle>,
    p: V,
    axes: &Axes,
    laws: &BushingLaws,
    preload: [f64; 6],
) -> BushingLine {
    BushingLine {
        name: name.into(),
        body_i: bi,
        body_j: bj,
        point: p,
        axes: *axes,
        stiffness: laws.stiffness.clone(),
        damping: laws.damping.clone(),
        preload,
    }
}
