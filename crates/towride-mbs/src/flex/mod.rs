//! Flexible bodies from beam finite-element models: 3D Timoshenko beams, rigid spiders,
//! Craig-Bampton reduction orthonormalised into a free-free-like mode table, mode
//! selection, and the data a floating-frame modal body needs ([`ModalData`]).
//!
//! Pipeline: `flex/*.toml` -> [`Mesh`] (checked, variant applied) -> [`Assembly`]
//! (K, M; spiders eliminated) -> [`CraigBampton`] (constraint + fixed-interface modes,
//! orthonormalised, rigid-body modes identified) -> [`ModalData`] (elastic modes, shapes
//! at interface and marker nodes, invariants, damping, selection). [`FlexBody::load`]
//! runs it all. Formulas and sources: `docs/flex.md`.

pub(crate) mod assemble;
pub mod beam;
pub mod character;
pub mod craig_bampton;
pub(crate) mod damping;
pub mod feedback;
pub(crate) mod input;
pub use input::{RuleIn, SelectionIn};
pub(crate) mod invariants;
pub(crate) mod material;
pub(crate) mod mesh;
pub(crate) mod modal;
pub mod modes;
pub mod report;
pub mod section;
pub mod selection;
pub mod stress;

use std::path::Path;

pub use assemble::Assembly;
pub use craig_bampton::{CraigBampton, ModeKind, ModeRow};
pub use damping::Damping;
pub use invariants::Invariants;
pub use mesh::Mesh;
pub use modal::{ModalData, ModalMode, ModalNode, NodeKind, Skeleton};
pub use selection::{LoadPath, Rule, Selection};

use crate::input::InputError;

/// A flexible-body failure: a bad file, or a model the numerics refuse.
#[derive(Clone, Debug, thiserror::Error)]
pub enum FlexError {
    /// A bad FE file.
    #[error(transparent)]
    Input(#[from] InputError),
    /// The file is fine but the model is not (a mechanism, too many modes asked...).
    #[error("{file}: {message}")]
    Model {
        /// The FE file.
        file: String,
        /// What is wrong.
        message: String,
    },
    /// A mode selection that cannot be made as asked.
    #[error("{0}")]
    Selection(String),
    /// The matrices refuse a factorisation or an eigensolution (a mechanism, a massless
    /// part, too many modes asked).
    #[error("{0}")]
    Numerics(String),
}

/// Choices that override the file's.
#[derive(Clone, Debug, Default)]
pub struct Options {
    /// Fixed-interface modes of the reduction (file: `fixed_interface_modes`).
    pub fixed_interface_modes: Option<usize>,
    /// Mode selection (file: `[selection]`).
    pub rule: Option<Rule>,
}

/// A flexible body: the FE model, its reduction, mode table, selection and modal data.
#[derive(Clone, Debug)]
pub struct FlexBody {
    /// The checked beam mesh.
    pub mesh: Mesh,
    /// Stiffness and mass matrices in the independent DOFs.
    pub assembly: Assembly,
    /// The Craig-Bampton reduction.
    pub cb: CraigBampton,
    /// The mode-selection rule in force (the options' rule, else the file's).
    pub rule: Rule,
    /// What `rule` keeps, with the load-path shares when it is that rule.
    pub selection: Selection,
    /// All elastic modes, flagged `selected` by `rule`; `modal.selected()` keeps those.
    pub modal: ModalData,
}

impl FlexBody {
    /// Reads `path` (variant `variant`, None for the base sections) and reduces it.
    pub fn load(
        path: &Path,
        variant: Option<u32>,
        options: &Options,
        loader: &crate::input::Loader,
    ) -> Result<FlexBody, FlexError> {
        let mesh = Mesh::read(path, variant, loader)?;
        FlexBody::from_mesh(mesh, options)
    }

    /// The table of the orthonormalised modes, rigid-body modes included, with their
    /// effective masses and kinetic energy by section. Made on request: a vehicle's
    /// modal body does not need it, and with 100 modes it cost a third of the body's
    /// reduction.
    pub fn table(&self) -> Vec<ModeRow> {
        craig_bampton::mode_table(&self.mesh, &self.assembly, &self.cb)
    }

    /// Reduces an already built mesh: assembly, Craig-Bampton reduction, modal data and
    /// selection.
    pub fn from_mesh(mesh: Mesh, options: &Options) -> Result<FlexBody, FlexError> {
        let model_err = |e: FlexError| FlexError::Model {
            file: mesh.path.display().to_string(),
            message: e.to_string(),
        };
        let assembly = Assembly::new(&mesh);
        let n_fixed = options
            .fixed_interface_modes
            .unwrap_or(mesh.fixed_interface_modes);
        let cb = craig_bampton::reduce(&mesh, &assembly, n_fixed).map_err(model_err)?;
        let mut modal = ModalData::build(&mesh, &assembly, &cb);
        let rule = options
            .rule
            .clone()
            .unwrap_or_else(|| mesh.selection.clone());
        let selection = selection::select(&modal, &rule).map_err(model_err)?;
        modal.set_selection(&selection.selected);
        Ok(FlexBody {
            mesh,
            assembly,
            cb,
            rule,
            selection,
            modal,
        })
    }
}

/// The modal data of `path` / `variant` with the file's selection flagged.
pub fn modal_data(path: &Path, variant: Option<u32>) -> Result<ModalData, FlexError> {
    let loader = crate::input::Loader::new();
    Ok(FlexBody::load(path, variant, &Options::default(), &loader)?.modal)
}
