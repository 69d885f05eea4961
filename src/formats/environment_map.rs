//! Environment maps as files: Radiance `.hdr` and OpenEXR `.exr`, read as untrusted input
//! (sizes checked before any texel is allocated; see [`crate::lighting`] for the mapping).

use std::fs::File;
use std::io::{BufReader, Read, Seek, SeekFrom};
use std::path::Path;

use crate::lighting::errors::{EnvironmentError, check_size};

/// How much of a Radiance file's start may hold its header and dimension line. The image
/// crate reads header lines without a length limit, so a file without newlines would be
/// read whole into one line; real headers are a few hundred bytes.
const HDR_HEADER_LIMIT: usize = 64 << 10;

/// Size and texels of a Radiance RGBE file, its size checked before pixels are decoded.
pub(crate) fn read_hdr(path: &Path) -> Result<(u32, u32, Vec<[f32; 3]>), EnvironmentError> {
    use hdr_image::ImageDecoder;
    use hdr_image::codecs::hdr::HdrDecoder;
    let io = |source| EnvironmentError::Io {
        path: path.to_path_buf(),
        source,
    };
    let hdr = |source| EnvironmentError::Hdr {
        path: path.to_path_buf(),
        source,
    };
    let invalid = |message: &str| EnvironmentError::Invalid {
        path: path.to_path_buf(),
        message: message.to_string(),
    };
    let mut file = File::open(path).map_err(io)?;
    let mut start = Vec::new();
    (&mut file)
        .take(HDR_HEADER_LIMIT as u64)
        .read_to_end(&mut start)
        .map_err(io)?;
    // Radiance files start with "#?" and a program name: "#?RADIANCE" usually, "#?RGBE" from
    // some writers. The decoder's strict mode knows only the first, so the signature is
    // checked here and the decoder runs non-strict, reading it as a comment.
    if !start.starts_with(b"#?") {
        return Err(invalid("not a Radiance file: it does not start with '#?'"));
    }
    // The header ends with an empty line and the dimension line follows; both must lie in
    // the first HDR_HEADER_LIMIT bytes (a shorter file that lacks them is left to the
    // decoder, which reports the truncation).
    let header_end = start.windows(2).position(|w| w == b"\n\n");
    let complete = header_end.is_some_and(|end| start[end + 2..].contains(&b'\n'));
    if start.len() == HDR_HEADER_LIMIT && !complete {
        return Err(invalid(
            "the header and dimension line do not end within the first 64 KiB",
        ));
    }
    file.seek(SeekFrom::Start(0)).map_err(io)?;
    let decoder = HdrDecoder::new_nonstrict(BufReader::new(file)).map_err(hdr)?;
    let (width, height) = decoder.dimensions();
    check_size(width as u64, height as u64).map_err(|problem| EnvironmentError::Content {
        path: path.to_path_buf(),
        problem,
    })?;
    // A zeroed allocation: on Linux its pages are only committed as the decoder fills them,
    // so a truncated file claiming a large size costs little memory before it fails.
    let mut texels = vec![[0.0f32; 3]; width as usize * height as usize];
    decoder
        .read_image(bytemuck::cast_slice_mut(&mut texels))
        .map_err(hdr)?;
    Ok((width, height, texels))
}

/// Texels being read from an EXR layer.
struct ExrTexels {
    width: usize,
    texels: Vec<[f32; 3]>,
}

/// Size and texels of the first RGB layer of an OpenEXR file, the sizes of every RGB layer
/// checked from the headers before pixels are decoded.
pub(crate) fn read_exr(path: &Path) -> Result<(u32, u32, Vec<[f32; 3]>), EnvironmentError> {
    use exr::prelude::*;
    let invalid = |message: String| EnvironmentError::Invalid {
        path: path.to_path_buf(),
        message,
    };
    let exr_error = |source| EnvironmentError::Exr {
        path: path.to_path_buf(),
        source,
    };
    // A missing file is an I/O error naming the file, not a format error.
    std::fs::metadata(path).map_err(|source| EnvironmentError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let meta = exr::meta::MetaData::read_from_file(path, false).map_err(exr_error)?;
    let rgb = ["R", "G", "B"];
    let is_rgb = |header: &&exr::meta::header::Header| {
        rgb.iter()
            .all(|name| header.channels.list.iter().any(|c| c.name.eq(name)))
    };
    // The reader below takes the first layer with R, G and B; every such layer is checked,
    // so whichever it takes has been.
    let mut found = false;
    for header in meta.headers.iter().filter(is_rgb) {
        found = true;
        let size = header.layer_size;
        check_size(size.width() as u64, size.height() as u64).map_err(|problem| {
            EnvironmentError::Content {
                path: path.to_path_buf(),
                problem,
            }
        })?;
        if header.deep {
            return Err(invalid("its RGB layer holds deep data".into()));
        }
        for channel in &header.channels.list {
            if rgb.iter().any(|name| channel.name.eq(name)) && channel.sampling != Vec2(1, 1) {
                return Err(invalid(format!(
                    "channel {} is subsampled: environments need every texel",
                    channel.name
                )));
            }
        }
    }
    if !found {
        return Err(invalid("has no layer with R, G and B channels".into()));
    }
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .rgb_channels(
            |size: Vec2<usize>, _: &RgbChannels| ExrTexels {
                width: size.width(),
                texels: vec![[0.0; 3]; size.area()],
            },
            |pixels: &mut ExrTexels, at: Vec2<usize>, (r, g, b): (f32, f32, f32)| {
                let index = at.y() * pixels.width + at.x();
                if let Some(texel) = pixels.texels.get_mut(index) {
                    *texel = [r, g, b];
                }
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .map_err(exr_error)?;
    let size = image.layer_data.size;
    let texels = image.layer_data.channel_data.pixels.texels;
    // The sizes were checked above, so these conversions cannot truncate.
    Ok((size.width() as u32, size.height() as u32, texels))
}
