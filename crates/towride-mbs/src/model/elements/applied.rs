//! A load of time on one marker: a force and a torque, components in world axes or in
//! the marker's own axes.

use serde::Deserialize;

use super::{ElementLoad, FieldError, ForceElement, Frame, Measure, SIX};
use crate::model::builder::{AppliedLine, MarkerHandle, ModelBuilder};
use crate::model::dual::Scalar;
use crate::model::function::TimeFunction;
use crate::model::math::{cst3, mvc, V3};

/// Force and torque of time on marker i.
#[derive(Clone, Debug)]
pub struct Applied {
    /// Name, unique among the elements.
    pub name: String,
    /// The marker loaded.
    pub i: MarkerHandle,
    /// Force components [N] (`None`: zero).
    pub force: [Option<TimeFunction>; 3],
    /// Torque components [N m].
    pub torque: [Option<TimeFunction>; 3],
    /// Components in the marker's axes (moving with the body), else in world axes.
    pub in_marker_axes: bool,
}

impl ForceElement for Applied {
    const TABLE: &'static str = "force";
    type Spec = AppliedSpec;
    type Markers = MarkerHandle;

    fn name(&self) -> &str {
        &self.name
    }

    fn markers(&self) -> MarkerHandle {
        self.i
    }

    fn check(&self) -> Result<(), FieldError> {
        for (key, fs) in [("force_n", &self.force), ("torque_n_m", &self.torque)] {
            for (c, f) in fs.iter().enumerate() {
                if let Some(f) = f {
                    f.check().map_err(|e| e.under(c).under(key))?;
                }
            }
        }
        Ok(())
    }

    fn load<S: Scalar>(&self, t: f64, i: &Frame<S>) -> ElementLoad<S> {
        let comp = |fs: &[Option<TimeFunction>; 3]| -> V3<S> {
            let local: [f64; 3] =
                std::array::from_fn(|c| fs[c].as_ref().map_or(0.0, |f| f.eval(t).0));
            if self.in_marker_axes {
                let a: [[S; 3]; 3] = i.0.axes.map(|r| r.map(|x| x.v));
                mvc(&a, &local)
            } else {
                cst3(&local)
            }
        };
        let force = comp(&self.force);
        let torque = comp(&self.torque);
        let measures = (0..3)
            .map(|c| (force[c], S::cst(0.0), S::cst(0.0)))
            .chain((0..3).map(|c| (torque[c], S::cst(0.0), S::cst(0.0))))
            .collect();
        ElementLoad {
            force,
            torque,
            measures,
        }
    }

    fn measures(&self) -> Vec<Measure> {
        SIX.to_vec()
    }

    fn add_from_file(s: &AppliedSpec, b: &mut ModelBuilder) -> Result<(), FieldError> {
        let body = b.body_by_name(&s.body).map_err(|e| e.under("body"))?;
        let axes = b.axes_from(s.z_axis, s.x_axis)?;
        let in_marker_axes = match s.axes.as_str() {
            "world" => false,
            "marker" => true,
            other => {
                return Err(FieldError::at(
                    "axes",
                    format!("'{other}': use \"world\" or \"marker\""),
                ))
            }
        };
        let fns = |spec: &Option<[FnSpec; 3]>| -> [Option<TimeFunction>; 3] {
            match spec {
                Some(s) => std::array::from_fn(|c| s[c].to_fn()),
                None => [None, None, None],
            }
        };
        b.applied(AppliedLine {
            name: s.name.clone(),
            body,
            point: s.position_m,
            axes,
            force: fns(&s.force_n),
            torque: fns(&s.torque_n_m),
            in_marker_axes,
        })
        .map_err(|e| e.into_field())?;
        Ok(())
    }
}

/// A number (constant) or a function of time.
#[derive(Deserialize, Debug, Clone)]
#[serde(untagged)]
pub enum FnSpec {
    /// A constant.
    Value(f64),
    /// A function of time.
    Function(TimeFunction),
}

impl FnSpec {
    fn to_fn(&self) -> Option<TimeFunction> {
        match self {
            FnSpec::Value(v) if *v == 0.0 => None,
            FnSpec::Value(v) => Some(TimeFunction::Constant { value: *v }),
            FnSpec::Function(f) => Some(f.clone()),
        }
    }
}

/// A `[[force]]` of a mechanism file.
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct AppliedSpec {
    /// Name, unique among the elements.
    pub name: String,
    /// The body loaded (not the ground).
    pub body: String,
    /// Point of application, world coordinates [m].
    pub position_m: [f64; 3],
    /// The marker's z axis.
    pub z_axis: Option<[f64; 3]>,
    /// The marker's x axis.
    pub x_axis: Option<[f64; 3]>,
    /// "world" or "marker" (the axes given here, moving with the body).
    #[serde(default = "world")]
    pub axes: String,
    /// Force components [N]: numbers or functions of time.
    pub force_n: Option<[FnSpec; 3]>,
    /// Torque components [N m].
    pub torque_n_m: Option<[FnSpec; 3]>,
}

fn world() -> String {
    "world".into()
}
