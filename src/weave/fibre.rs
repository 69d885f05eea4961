//! Fibre presets: the refractive index η of the fibres cloth is woven from.

use std::fmt;
use std::str::FromStr;

/// A fibre whose refractive index is known.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fibre {
    Silk,
    Polyester,
    Cotton,
    Linen,
    Wool,
    Nylon,
}

impl Fibre {
    pub const ALL: [Fibre; 6] = [
        Fibre::Silk,
        Fibre::Polyester,
        Fibre::Cotton,
        Fibre::Linen,
        Fibre::Wool,
        Fibre::Nylon,
    ];

    /// The preset's name, as commands and Python spell it.
    pub fn name(self) -> &'static str {
        match self {
            Fibre::Silk => "silk",
            Fibre::Polyester => "polyester",
            Fibre::Cotton => "cotton",
            Fibre::Linen => "linen",
            Fibre::Wool => "wool",
            Fibre::Nylon => "nylon",
        }
    }

    /// η of the fibre. Silk, polyester and linen take the values the paper fitted to its
    /// measured fabrics (docs/model.md#the-six-built-in-fabrics); cotton (cellulose, 1.53 to
    /// 1.58 across and along the fibre), wool (keratin, 1.55 to 1.56) and nylon 6 (1.53 to
    /// 1.58) take the middle of their handbook ranges, since the model has one η per thread
    /// and no birefringence.
    pub fn eta(self) -> f64 {
        match self {
            Fibre::Silk => 1.345,
            Fibre::Polyester => 1.539,
            Fibre::Cotton => 1.55,
            Fibre::Linen => 1.46,
            Fibre::Wool => 1.55,
            Fibre::Nylon => 1.55,
        }
    }
}

impl fmt::Display for Fibre {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A fibre name none of [`Fibre::ALL`] has.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown fibre '{text}'; known: {}", Fibre::ALL.map(Fibre::name).join(", "))]
pub struct UnknownFibre {
    pub text: String,
}

impl FromStr for Fibre {
    type Err = UnknownFibre;

    fn from_str(text: &str) -> Result<Self, UnknownFibre> {
        Fibre::ALL
            .into_iter()
            .find(|f| f.name().eq_ignore_ascii_case(text.trim()))
            .ok_or_else(|| UnknownFibre {
                text: text.to_string(),
            })
    }
}
