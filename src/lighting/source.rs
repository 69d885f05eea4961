//! Where an environment comes from: the CLI's and scene files' `--env` word.

use std::fmt;
use std::path::PathBuf;
use std::str::FromStr;

use super::{Environment, EnvironmentError, GeneratedEnvironment};

/// Where the environment comes from: the CLI's `--env` word.
#[derive(Debug, Clone, PartialEq)]
pub enum EnvironmentSource {
    /// `none`: no environment lighting.
    None,
    /// `default`: the built-in [`Environment::studio`].
    Default,
    /// `uniform`: constant radiance 1, the white furnace ([`Environment::uniform`]).
    Uniform,
    /// `studio`, `sky`, `overcast`, `interior`: a built-in environment
    /// ([`GeneratedEnvironment`]; `studio` is what `default` names).
    Generated(GeneratedEnvironment),
    /// Anything else: an `.hdr` or `.exr` file ([`Environment::load`]). A file named like
    /// one of the words above is written with a directory, `./default`.
    File(PathBuf),
}

impl EnvironmentSource {
    /// The environment this source names; `None` for [`EnvironmentSource::None`].
    pub fn load(&self) -> Result<Option<Environment>, EnvironmentError> {
        Ok(match self {
            Self::None => None,
            Self::Default => Some(Environment::studio()),
            Self::Uniform => Some(Environment::uniform(1.0)),
            Self::Generated(generated) => Some(generated.environment()),
            Self::File(path) => Some(Environment::load(path)?),
        })
    }
}

impl FromStr for EnvironmentSource {
    type Err = EnvironmentError;

    fn from_str(word: &str) -> Result<Self, Self::Err> {
        Ok(match word {
            "" => return Err(EnvironmentError::EmptySource),
            "none" => Self::None,
            "default" => Self::Default,
            "uniform" => Self::Uniform,
            word => match GeneratedEnvironment::from_name(word) {
                Some(generated) => Self::Generated(generated),
                None => Self::File(PathBuf::from(word)),
            },
        })
    }
}

impl fmt::Display for EnvironmentSource {
    /// The word that parses back to this source: a file named like a keyword gets `./`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::None => f.write_str("none"),
            Self::Default => f.write_str("default"),
            Self::Uniform => f.write_str("uniform"),
            Self::Generated(generated) => f.write_str(generated.name()),
            Self::File(path) => {
                let text = path.display().to_string();
                if matches!(text.as_str(), "none" | "default" | "uniform")
                    || GeneratedEnvironment::from_name(&text).is_some()
                {
                    write!(f, "./{text}")
                } else {
                    f.write_str(&text)
                }
            }
        }
    }
}
