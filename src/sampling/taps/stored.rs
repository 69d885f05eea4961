//! Sample taps kept between runs: what identifies the code that built them, and taps made
//! again from stored words, checked ([`SampleTaps::from_words`]). The file that holds them
//! is `crate::formats::taps_file`.

use super::{SampleTaps, TAP_NODES, TAP_WORDS};

/// Revision of the code that builds taps, recorded with stored taps: raised whenever the
/// same table and sample count would build different words (the strata, the points per
/// node, the moment matching, the packing, the table's f64 batch lookup), so that taps
/// stored by an earlier build are not used.
pub const TAPS_REVISION: u32 = 1;

/// Why stored words are not a fabric's taps.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum TapsWordsError {
    #[error("{words} words do not hold {samples} taps for each of {TAP_NODES} nodes")]
    Length { samples: u32, words: usize },
    #[error("the first word says {stored} samples, the header {samples}")]
    Samples { samples: u32, stored: u32 },
    #[error("the weight scale {0} is not a positive finite number")]
    Scale(f32),
}

impl SampleTaps {
    /// The words a build for `samples` per pixel needs: the header's four and [`TAP_WORDS`]
    /// per tap; `None` where that overflows.
    pub fn word_count(samples: u32) -> Option<usize> {
        TAP_NODES
            .checked_mul(samples as usize)?
            .checked_add(1)?
            .checked_mul(TAP_WORDS)
    }

    /// The taps whose [`Self::words`] are `words`, for `samples` per pixel: the length, the
    /// sample count in the first word and the weight scale are checked (every other word
    /// reads as some tap, so nothing else can make the taps unusable).
    pub fn from_words(samples: u32, words: Vec<u32>) -> Result<Self, TapsWordsError> {
        if samples == 0 || Self::word_count(samples) != Some(words.len()) {
            return Err(TapsWordsError::Length {
                samples,
                words: words.len(),
            });
        }
        if words[0] != samples {
            return Err(TapsWordsError::Samples {
                samples,
                stored: words[0],
            });
        }
        let scale = f32::from_bits(words[1]);
        if !(scale.is_finite() && scale > 0.0) {
            return Err(TapsWordsError::Scale(scale));
        }
        Ok(Self { samples, words })
    }
}
