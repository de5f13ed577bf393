//! The options of `lopin sweep` checked into a plan: the parameter and its values (`--param`,
//! parsed by clap through [`parse_param`], each checked against the problem before anything is
//! written), the predictor (a clap `ValueEnum` mapped onto the
//! core's [`Predictor`]), the mode (warm, cold, compare-cold), the solver settings it runs with,
//! the sweep header a resume must match (with the fingerprints of the resolved scene and of the
//! settings, so an edited scene file or other settings are seen) and the directory.

use std::path::PathBuf;

use anyhow::Context;
use lopin_core::study::design::parse_values;
use lopin_core::study::Predictor;
use lopin_core::Parameter;

use super::SweepArgs;
use crate::cli::setup::Prepared;
use crate::cli::sweep::records::Header;
use crate::run_dir::fingerprint;

/// `--param NAME=VALUES`: the parameter and its values.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamValues {
    pub parameter: Parameter,
    pub values: Vec<f64>,
}

/// Parses `--param` (clap's value parser).
pub fn parse_param(text: &str) -> Result<ParamValues, String> {
    let (name, values) = text.split_once('=').ok_or_else(|| {
        format!("--param must look like f=0:0.5:0.05 or f=0.1,0.2 (got `{text}`)")
    })?;
    Ok(ParamValues {
        parameter: Parameter::parse(name).map_err(|e| e.to_string())?,
        values: parse_values(values).map_err(|e| e.to_string())?,
    })
}

/// `--predictor`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum PredictorArg {
    /// The converged state of the previous value.
    Previous,
    /// Linear extrapolation from the two previous converged states.
    Linear,
    /// Linear extrapolation of the time-smoothed change only (the alternating content of the
    /// change is not extrapolated).
    Smooth,
}

impl From<PredictorArg> for Predictor {
    fn from(p: PredictorArg) -> Self {
        match p {
            PredictorArg::Previous => Predictor::Previous,
            PredictorArg::Linear => Predictor::Linear,
            PredictorArg::Smooth => Predictor::Smooth,
        }
    }
}

/// How each value is started.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// From the predictor's state.
    Warm,
    /// From scratch (`--cold`).
    Cold,
    /// Warm, and each value cold too (`--compare-cold`).
    CompareCold,
}

impl Mode {
    /// Name in the header, run.json and the JSON report.
    pub fn name(self) -> &'static str {
        match self {
            Mode::Warm => "warm",
            Mode::Cold => "cold",
            Mode::CompareCold => "compare-cold",
        }
    }
}

/// A checked sweep.
#[derive(Debug, Clone)]
pub struct Plan {
    pub parameter: Parameter,
    pub values: Vec<f64>,
    pub predictor: Predictor,
    pub mode: Mode,
    /// What the sweep directory records (and a resume must match).
    pub header: Header,
    pub dir: PathBuf,
}

impl Plan {
    /// The plan of `args` on a prepared solver, whose settings it sets (`--no-skip`).
    pub fn new(args: &SweepArgs, prepared: &mut Prepared) -> anyhow::Result<Plan> {
        let ParamValues { parameter, values } = args.param.clone();
        // every value is checked against the problem before the sweep folder is made
        for &v in &values {
            parameter
                .check_for(prepared.solver.problem(), v)
                .with_context(|| format!("--param {} = {v:?}", parameter.name()))?;
        }
        let predictor = Predictor::from(args.predictor);
        let solver = &mut prepared.solver;
        let mut settings = *solver.settings();
        settings.skip_unchanged = !args.no_skip;
        solver.set_settings(settings)?;
        let mode = if args.cold {
            Mode::Cold
        } else if args.compare_cold {
            Mode::CompareCold
        } else {
            Mode::Warm
        };
        let header = Header {
            scene: prepared.spec.name.clone(),
            scene_hash: fingerprint::of_scene(&prepared.spec, &prepared.assignments),
            settings_hash: fingerprint::of_settings(&settings),
            parameter: parameter.name().into(),
            values: values.clone(),
            mode: mode.name().into(),
            predictor: predictor.name().into(),
            tol: settings.tol,
            k: settings.k,
            mu: settings.mu,
            refine: args.scene.refine,
            split: args.scene.split,
            skip_unchanged: settings.skip_unchanged,
        };
        let dir = args.out.clone().unwrap_or_else(|| {
            PathBuf::from(format!("out/sweep-{}-{}", header.scene, header.parameter))
        });
        Ok(Plan {
            parameter,
            values,
            predictor,
            mode,
            header,
            dir,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn param_parses_name_and_values_and_says_what_is_wrong() {
        let p = parse_param("f=0.1,0.2").expect("parses");
        assert_eq!(p.parameter, Parameter::Friction);
        assert_eq!(p.values, vec![0.1, 0.2]);
        assert!(parse_param("f")
            .expect_err("no =")
            .contains("must look like"));
        assert!(parse_param("mass=1").expect_err("unknown").contains("mass"));
    }
}
