//! Options and helpers shared by several commands.

use clothbake::evaluator::direct::Direct;
use clothbake::evaluator::table::BakedTable;
use clothbake::evaluator::{
    EvaluationContext, Evaluator, EvaluatorError, EvaluatorSpec, FabricEvaluator,
};
use clothbake::model::curve::DEFAULT_PAPER_SAMPLES;
use clothbake::model::{Fabric, ResonantNodes};
use clothbake::table::Layout;
use std::path::Path;
use std::sync::Arc;

/// Options that do not fit together, named as the user wrote them.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct UsageError(pub String);

/// The values of the older option `render --shader` / `view --shader` and the evaluator
/// each stands for (`direct` was paper mode's name in the shader before every command spelt
/// evaluators one way).
#[cfg(feature = "runtime")]
pub const SHADER_WORDS: &[(&str, &str)] = &[
    ("lookup", "table"),
    ("paper", "paper"),
    ("direct", "paper"),
    ("resonant", "resonant"),
    ("constant", "constant"),
];

/// The value of `--shader` as given, else `paper` where `--samples` is given alone (as
/// `eval --samples` selects paper mode), else `lookup`.
#[cfg(feature = "runtime")]
pub fn older_shader_word(shader: Option<&str>, samples: Option<u32>) -> &str {
    shader.unwrap_or(if samples.is_some() { "paper" } else { "lookup" })
}

/// The values of the older option `eval --integration` and the evaluator each stands for.
pub const INTEGRATION_WORDS: &[(&str, &str)] = &[
    ("direct", "direct"),
    ("paper", "paper"),
    ("resonant", "resonant"),
];

/// The words of `words`, for clap's list of possible values.
pub fn older_words(words: &'static [(&'static str, &'static str)]) -> Vec<&'static str> {
    words.iter().map(|(word, _)| *word).collect()
}

/// The evaluator spelling that the older options select: `word`, the value of `option`
/// (`--shader`, `--integration`), stands for an evaluator by `words`; `--samples` becomes
/// paper mode's N and the node options the resonant quadrature's counts. Where they do not
/// fit the evaluator, the error names the options as the user wrote them. This is the one
/// place the older options are read.
pub fn older_spelling(
    option: &str,
    word: &str,
    words: &[(&str, &str)],
    samples: Option<u32>,
    nodes: &NodeArgs,
) -> Result<String, UsageError> {
    let name = words
        .iter()
        .find(|(w, _)| *w == word)
        .map(|(_, name)| *name)
        .ok_or_else(|| UsageError(format!("{option} {word}: not one of its values")))?;
    let nodes = nodes.nodes(name == "resonant", &format!("{option} resonant"))?;
    match (name, samples) {
        ("paper", samples) => Ok(format!(
            "paper:{}",
            samples.unwrap_or(DEFAULT_PAPER_SAMPLES)
        )),
        (_, Some(_)) => Err(UsageError(format!(
            "--samples applies to paper mode, not {option} {word}"
        ))),
        ("resonant", None) => Ok(format!("resonant:{nodes}")),
        (name, None) => Ok(name.to_string()),
    }
}

/// The resonant quadrature's node counts (`eval --integration resonant`,
/// `render --shader resonant`); each defaults to `ResonantNodes::DEFAULT`'s.
#[derive(clap::Args)]
pub struct NodeArgs {
    /// Resonant quadrature: Gauss–Legendre nodes per curve segment on the surface lobe.
    #[arg(long, value_parser = resonant_count)]
    surface_nodes: Option<u32>,
    /// Resonant quadrature: nodes per segment on the volume lobe.
    #[arg(long, value_parser = resonant_count)]
    volume_nodes: Option<u32>,
    /// Resonant quadrature: nodes per segment for ⟨P⟩ and the kd term.
    #[arg(long, value_parser = resonant_count)]
    base_nodes: Option<u32>,
}

impl NodeArgs {
    /// The node counts, or an error naming `selector` when any is given but `selected` is
    /// false (the options belong to the resonant rule only).
    pub fn nodes(&self, selected: bool, selector: &str) -> Result<ResonantNodes, UsageError> {
        let given = [self.surface_nodes, self.volume_nodes, self.base_nodes];
        if !selected && given.iter().any(Option::is_some) {
            return Err(UsageError(format!(
                "--surface-nodes, --volume-nodes and --base-nodes apply to {selector}"
            )));
        }
        let d = ResonantNodes::DEFAULT;
        Ok(ResonantNodes {
            surface: self.surface_nodes.unwrap_or(d.surface),
            volume: self.volume_nodes.unwrap_or(d.volume),
            base: self.base_nodes.unwrap_or(d.base),
        })
    }
}

/// Why one of the value parsers below refuses a command-line value (clap names the option).
#[derive(Debug, thiserror::Error)]
pub enum ValueError {
    #[error(transparent)]
    Number(#[from] std::num::ParseIntError),
    #[error("must be in 1..={0}")]
    OutOfRange(u32),
    #[error("unknown layout '{name}'; layouts: {known}")]
    UnknownLayout { name: String, known: String },
}

/// A resonant node count, 1..=ResonantNodes::MAX.
fn resonant_count(text: &str) -> Result<u32, ValueError> {
    let n: u32 = text.parse()?;
    if (1..=ResonantNodes::MAX).contains(&n) {
        Ok(n)
    } else {
        Err(ValueError::OutOfRange(ResonantNodes::MAX))
    }
}

/// A table layout by its registered name.
pub fn parse_layout(name: &str) -> Result<Layout, ValueError> {
    Layout::from_name(name).ok_or_else(|| ValueError::UnknownLayout {
        name: name.to_string(),
        known: Layout::ALL
            .iter()
            .map(|l| l.name())
            .collect::<Vec<_>>()
            .join(", "),
    })
}

/// The evaluation of `fabric` that `--evaluator` names (`--table PATH` is
/// `--evaluator table:PATH`), by default the converged direct rule.
pub fn evaluation_of(
    fabric: &Fabric,
    evaluator: Option<&EvaluatorSpec>,
    table: Option<&Path>,
) -> Result<Box<dyn FabricEvaluator>, EvaluatorError> {
    let evaluator: Arc<dyn Evaluator> = match (evaluator, table) {
        (Some(spec), _) => spec.0.clone(),
        (None, Some(path)) => Arc::new(BakedTable {
            path: Some(path.to_path_buf()),
        }),
        (None, None) => Arc::new(Direct),
    };
    evaluator.prepare(fabric, &EvaluationContext::default())
}

#[cfg(feature = "runtime")]
pub use runtime::*;

/// Options of the commands that show a scene (`render`, `view`).
#[cfg(feature = "runtime")]
mod runtime {
    use clothbake::lighting::bright_sources::MAX_SOURCES;
    use clothbake::lighting::{EnvironmentError, EnvironmentSource};
    use clothbake::scene::{MAX_ENVIRONMENT_SAMPLES, Scene, SceneError};
    use std::path::PathBuf;

    /// What `render` and `view` show: a scene, its tables and optionally a user's mesh.
    #[derive(clap::Args)]
    pub struct SceneArgs {
        /// Scene file (TOML): fabrics, camera, lights, mesh (default: tables/scene.toml's).
        #[arg(long)]
        scene: Option<PathBuf>,
        /// Directory of baked tables (NAME.exr).
        #[arg(long, default_value = "tables")]
        pub tables: PathBuf,
        /// OBJ mesh with UVs to show instead of the scene's (the camera is aimed at it).
        #[arg(long)]
        pub mesh: Option<PathBuf>,
        /// Environment light: a built-in one, `default` or `studio` (soft boxes), `sky` (a clear
        /// sky with a 0.5° sun), `overcast`, `interior` (windows and lamps); `uniform` (radiance
        /// 1: the white furnace); `none`; or an equirectangular .hdr or .exr file (default: the
        /// scene's).
        #[arg(long, value_parser = parse_environment)]
        env: Option<EnvironmentSource>,
        /// Filtered importance samples per pixel of the environment light (default: the
        /// scene's, 96 in the built-in scene).
        #[arg(long, value_parser = clap::value_parser!(u32).range(1..=MAX_ENVIRONMENT_SAMPLES as i64))]
        env_samples: Option<u32>,
        /// Most compact bright sources (sun, lamps) of the environment lit as directional
        /// lights, the rest of the map sampled; 0 samples the whole map (default: the
        /// scene's, 8).
        #[arg(long, value_parser = clap::value_parser!(u32).range(0..=MAX_SOURCES as i64))]
        env_sources: Option<u32>,
        /// Switch the scene's lights off (the environment alone).
        #[arg(long)]
        no_lights: bool,
    }

    impl SceneArgs {
        /// The scene file's scene, or the built-in default scene, with the environment and
        /// lights the options ask for.
        pub fn load(&self) -> Result<Scene, SceneError> {
            let mut scene = match &self.scene {
                Some(path) => Scene::load(path)?,
                None => Scene::builtin(),
            };
            if let Some(source) = &self.env {
                scene.environment.source = source.clone();
            }
            if let Some(samples) = self.env_samples {
                scene.environment.samples = samples;
            }
            if let Some(sources) = self.env_sources {
                scene.environment.sources = sources as usize;
            }
            if self.no_lights {
                scene.lights.clear();
            }
            Ok(scene)
        }
    }

    fn parse_environment(word: &str) -> Result<EnvironmentSource, EnvironmentError> {
        word.parse()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn no_nodes() -> NodeArgs {
        NodeArgs {
            surface_nodes: None,
            volume_nodes: None,
            base_nodes: None,
        }
    }

    #[test]
    fn every_older_word_names_a_spelling_that_parses() {
        #[cfg(feature = "runtime")]
        let tables = [INTEGRATION_WORDS, SHADER_WORDS];
        #[cfg(not(feature = "runtime"))]
        let tables = [INTEGRATION_WORDS];
        for words in tables {
            for (word, name) in words {
                let spelling = older_spelling("--option", word, words, None, &no_nodes()).unwrap();
                let evaluator = clothbake::evaluator::parse(&spelling).unwrap();
                assert!(evaluator.spelling().starts_with(name), "{word}: {spelling}");
            }
        }
        let paper = older_spelling(
            "--integration",
            "paper",
            INTEGRATION_WORDS,
            Some(8),
            &no_nodes(),
        );
        assert_eq!(paper.unwrap(), "paper:8");
        let nodes = NodeArgs {
            base_nodes: Some(3),
            ..no_nodes()
        };
        let resonant = older_spelling("--integration", "resonant", INTEGRATION_WORDS, None, &nodes);
        let d = ResonantNodes::DEFAULT;
        assert_eq!(
            resonant.unwrap(),
            format!("resonant:{}/{}/3", d.surface, d.volume)
        );
    }

    #[test]
    fn older_options_that_do_not_fit_their_evaluator_are_named() {
        let error = |word, samples, nodes: &NodeArgs| {
            older_spelling("--integration", word, INTEGRATION_WORDS, samples, nodes)
                .unwrap_err()
                .to_string()
        };
        assert!(error("direct", Some(8), &no_nodes()).contains("not --integration direct"));
        let nodes = NodeArgs {
            surface_nodes: Some(3),
            ..no_nodes()
        };
        assert!(error("paper", None, &nodes).contains("apply to --integration resonant"));
        assert!(error("midpoint", None, &no_nodes()).contains("--integration midpoint"));
    }
}
