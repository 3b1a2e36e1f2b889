//! Film files: an OpenEXR image whose `R`, `G`, `B` channels are the mean radiance (any viewer
//! shows it) and whose `ggx.*` channels hold the exact film ([`SampleSum`] per pixel), with the
//! render's identity in the header ([`FilmInfo`]). `ggx merge` adds such files bit for bit and
//! `ggx render --resume` continues one.
//!
//! Why not `f32` sums: `f32` addition rounds, so the sum of two parts differs from the sum of
//! the whole in the last bits; an `f64` sum stored as two `f32` layers would still depend on
//! the order of additions. The 128-bit fixed-point sums are exact under any grouping, so each
//! channel's sum is stored whole, as four little-endian `u32` words (`ggx.sum.R.0` lowest).

use std::collections::HashMap;
use std::path::Path;

use exr::prelude::{
    AnyChannel, AnyChannels, AttributeValue, Encoding, FlatSamples, Image, Layer, LayerAttributes, ReadChannels,
    ReadLayers, Text, WritableImage, read,
};
use glam::Vec3;

use crate::atomic::write_atomically;
use crate::{Film, OutputError, OutputOptions, Window};

/// Value of the `ggx.film` attribute: the version of this layout.
const FORMAT: &str = "1";

/// Channels of a film file: `R`, `G`, `B`, four words for each of the three sums, the sample
/// and the invalid counts.
const CHANNELS: usize = 3 + 12 + 2;

/// What a film file says about the render that made it: what must agree for two films to be
/// merged, and figures for people ([`FilmInfo::stats`]).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct FilmInfo {
    /// The scene file, as given on the command line (informational).
    pub scene: String,
    /// Hash of everything in the loaded scene that decides a sample's value (hex).
    pub scene_hash: String,
    /// The scene's seed.
    pub seed: u64,
    /// The animation frame.
    pub frame: u32,
    /// The sample range `[start, end)` that was asked for; pixel `i` holds samples
    /// `[start, start + samples_i)` of it.
    pub samples: [u32; 2],
    /// Samples per pixel of the whole render the range is part of (`ggx merge` reports what
    /// the parts lack of `[0, total)`).
    pub total: u32,
    /// The pixel window `[x0, y0, x1, y1)` that was asked for.
    pub window: Window,
    /// The backend that rendered it (`cpu`, `wgpu`): backends differ in the last bits.
    pub backend: String,
    /// The ggx version that rendered it.
    pub version: String,
    /// Other figures (render time, rates, adapter, kernel): written, never compared.
    pub stats: Vec<(String, String)>,
}

impl FilmInfo {
    /// The header attributes, `ggx.<name>` = text.
    fn attributes(&self) -> Vec<(String, String)> {
        let [x0, y0, x1, y1] = self.window;
        let mut list = vec![
            ("scene".to_owned(), self.scene.clone()),
            ("sceneHash".to_owned(), self.scene_hash.clone()),
            ("seed".to_owned(), self.seed.to_string()),
            ("frame".to_owned(), self.frame.to_string()),
            ("samples".to_owned(), format!("{}..{}", self.samples[0], self.samples[1])),
            ("total".to_owned(), self.total.to_string()),
            ("window".to_owned(), format!("{x0},{y0},{x1},{y1}")),
            ("backend".to_owned(), self.backend.clone()),
            ("version".to_owned(), self.version.clone()),
        ];
        list.extend(self.stats.iter().map(|(k, v)| (format!("stats.{k}"), v.clone())));
        list
    }

    /// Parses the attributes written by [`FilmInfo::attributes`]; the error names the field.
    fn parse(attributes: &HashMap<String, String>) -> Result<Self, String> {
        let get = |name: &str| attributes.get(name).cloned().ok_or_else(|| format!("the header lacks ggx.{name}"));
        let number = |name: &str| -> Result<u64, String> {
            get(name)?.parse().map_err(|_| format!("ggx.{name} is not a whole number"))
        };
        let u32_of = |name: &str| -> Result<u32, String> {
            u32::try_from(number(name)?).map_err(|_| format!("ggx.{name} is out of range"))
        };
        let samples = get("samples")?;
        let samples = samples
            .split_once("..")
            .and_then(|(a, b)| Some([a.parse().ok()?, b.parse().ok()?]))
            .filter(|[a, b]| a <= b)
            .ok_or_else(|| format!("ggx.samples `{samples}` is not a range A..B"))?;
        let window = get("window")?;
        let parts: Vec<u32> = window.split(',').filter_map(|v| v.parse().ok()).collect();
        let window = <[u32; 4]>::try_from(parts)
            .ok()
            .filter(|[x0, y0, x1, y1]| x0 <= x1 && y0 <= y1)
            .ok_or_else(|| format!("ggx.window `{window}` is not x0,y0,x1,y1"))?;
        let mut stats: Vec<(String, String)> = attributes
            .iter()
            .filter_map(|(k, v)| k.strip_prefix("stats.").map(|k| (k.to_owned(), v.clone())))
            .collect();
        stats.sort();
        Ok(FilmInfo {
            scene: get("scene")?,
            scene_hash: get("sceneHash")?,
            seed: number("seed")?,
            frame: u32_of("frame")?,
            samples,
            total: u32_of("total")?,
            window,
            backend: get("backend")?,
            version: get("version")?,
            stats,
        })
    }
}

/// Writes `film` to an EXR at `path`, atomically: `R`, `G`, `B` = its mean scaled by the
/// exposure of `options` (as [`crate::write_image`] writes EXR), `info` in the header, and, when
/// `exact`, the film's sums and counts.
pub fn write_film(
    path: &Path,
    info: &FilmInfo,
    film: &Film,
    exact: bool,
    options: &OutputOptions,
) -> Result<(), OutputError> {
    let (width, height) = (film.width(), film.height());
    if width == 0 || height == 0 {
        return Err(OutputError::Empty { path: path.to_owned(), width, height });
    }
    let scale = options.exposure_scale();
    let pixels: Vec<Vec3> = film.pixels().iter().map(|p| crate::output::expose(p.mean(), scale)).collect();
    let film = exact.then_some(film);
    let mut channels = exr::prelude::SmallVec::new();
    for (name, c) in [("R", 0), ("G", 1), ("B", 2)] {
        channels.push(AnyChannel::new(name, FlatSamples::F32(pixels.iter().map(|p| p[c]).collect())));
    }
    let mut attributes = LayerAttributes::default();
    let mut list = info.attributes();
    if let Some(film) = film {
        list.push(("film".to_owned(), FORMAT.to_owned()));
        for (name, c) in [("R", 0), ("G", 1), ("B", 2)] {
            for word in 0..4 {
                let data = film.pixels().iter().map(|p| (p.rgb[c] >> (32 * word)) as u32).collect();
                channels.push(AnyChannel::new(format!("ggx.sum.{name}.{word}").as_str(), FlatSamples::U32(data)));
            }
        }
        let samples = film.pixels().iter().map(|p| p.samples).collect();
        channels.push(AnyChannel::new("ggx.samples", FlatSamples::U32(samples)));
        let invalid = film.pixels().iter().map(|p| p.invalid).collect();
        channels.push(AnyChannel::new("ggx.invalid", FlatSamples::U32(invalid)));
    }
    for (key, value) in list {
        attributes
            .other
            .insert(Text::from(format!("ggx.{key}").as_str()), AttributeValue::Text(Text::from(value.as_str())));
    }
    let layer = Layer::new(
        (width as usize, height as usize),
        attributes,
        Encoding::SMALL_LOSSLESS,
        AnyChannels::sort(channels),
    );
    write_atomically(path, |out| {
        Image::from_layer(layer).write().to_buffered(out).map_err(|e| OutputError::Encode {
            path: path.to_owned(),
            format: "EXR",
            source: Box::new(e),
        })
    })
}

/// Reads only the header of a film file: its info and `[width, height]` (for checking and
/// ordering parts before their pixels are read).
pub fn read_film_info(path: &Path) -> Result<(FilmInfo, [u32; 2]), OutputError> {
    let invalid = |reason: String| OutputError::NotAFilm { path: path.to_owned(), reason };
    let meta = exr::meta::MetaData::read_from_file(path, false)
        .map_err(|source| OutputError::Decode { path: path.to_owned(), source })?;
    let header = meta.headers.first().ok_or_else(|| invalid("it has no layer".into()))?;
    let text = text_attributes(&header.own_attributes.other);
    if text.get("film").map(String::as_str) != Some(FORMAT) {
        return Err(invalid("it holds no exact film (render with --samples, --crop or --checkpoint)".into()));
    }
    let size = header.layer_size;
    match (u32::try_from(size.width()), u32::try_from(size.height())) {
        (Ok(w), Ok(h)) => Ok((FilmInfo::parse(&text).map_err(invalid)?, [w, h])),
        _ => Err(invalid(format!("its size {}x{} is too large", size.width(), size.height()))),
    }
}

/// The `ggx.*` text attributes, without the prefix.
fn text_attributes(other: &HashMap<Text, AttributeValue>) -> HashMap<String, String> {
    other
        .iter()
        .filter_map(|(k, v)| match v {
            AttributeValue::Text(t) => Some((k.to_string().strip_prefix("ggx.")?.to_owned(), t.to_string())),
            _ => None,
        })
        .collect()
}

/// Reads a film file written by [`write_film`] with the exact channels: its info and film.
/// Files larger than `max_pixels` are refused before their pixels are read.
pub fn read_film(path: &Path, max_pixels: u64) -> Result<(FilmInfo, Film), OutputError> {
    let invalid = |reason: String| OutputError::NotAFilm { path: path.to_owned(), reason };
    let meta = exr::meta::MetaData::read_from_file(path, false)
        .map_err(|source| OutputError::Decode { path: path.to_owned(), source })?;
    let header = meta.headers.first().ok_or_else(|| invalid("it has no layer".into()))?;
    if text_attributes(&header.own_attributes.other).get("film").map(String::as_str) != Some(FORMAT) {
        return Err(invalid("it holds no exact film (render with --samples, --crop or --checkpoint)".into()));
    }
    if meta.headers.len() != 1 || header.deep {
        return Err(invalid("a film file has exactly one flat layer".into()));
    }
    let size = header.layer_size;
    let (w, h) = (size.width() as u64, size.height() as u64);
    if w.saturating_mul(h) > max_pixels {
        return Err(invalid(format!("its {w}x{h} pixels exceed the limit of {max_pixels}")));
    }
    // What is read is allocated per channel and pixel: only the channels a film has, each
    // once, so memory is bounded by the pixel count checked above.
    let channels = &header.channels.list;
    if channels.len() != CHANNELS {
        return Err(invalid(format!("it has {} channels, a film has {CHANNELS}", channels.len())));
    }
    if let Some(c) = channels.iter().find(|c| c.sampling.x() != 1 || c.sampling.y() != 1) {
        return Err(invalid(format!("channel {} is subsampled", c.name)));
    }
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .map_err(|source| OutputError::Decode { path: path.to_owned(), source })?;
    let layer = image.layer_data;
    let text = text_attributes(&layer.attributes.other);
    if text.get("film").map(String::as_str) != Some(FORMAT) {
        return Err(invalid("it holds no exact film (render with --samples, --crop or --checkpoint)".into()));
    }
    let info = FilmInfo::parse(&text).map_err(invalid)?;
    let (width, height) = (u32::try_from(w), u32::try_from(h));
    let (Ok(width), Ok(height)) = (width, height) else {
        return Err(invalid(format!("its size {w}x{h} is too large")));
    };
    let channel = |name: &str| -> Result<&Vec<u32>, OutputError> {
        match layer.channel_data.list.iter().find(|c| c.name.to_string() == name).map(|c| &c.sample_data) {
            Some(FlatSamples::U32(v)) if v.len() as u64 == w * h => Ok(v),
            Some(_) => Err(invalid(format!("channel {name} is not u32 with one value per pixel"))),
            None => Err(invalid(format!("channel {name} is missing"))),
        }
    };
    let mut film = Film::try_new(width, height).map_err(|e| invalid(e.to_string()))?;
    for (c, name) in ["R", "G", "B"].iter().enumerate() {
        for word in 0..4 {
            let data = channel(&format!("ggx.sum.{name}.{word}"))?;
            for (p, &v) in film.pixels_mut().iter_mut().zip(data) {
                p.rgb[c] |= i128::from(v) << (32 * word);
            }
        }
    }
    let (samples, bad) = (channel("ggx.samples")?, channel("ggx.invalid")?);
    for ((p, &n), &b) in film.pixels_mut().iter_mut().zip(samples).zip(bad) {
        p.samples = n;
        p.invalid = b.min(n);
    }
    Ok((info, film))
}

/// Shorthand used by tests: one pixel's sum.
#[cfg(test)]
fn sum(v: f32, samples: u32) -> crate::SampleSum {
    let mut s = crate::SampleSum::default();
    s.add_summed(Vec3::splat(v), samples);
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn info() -> FilmInfo {
        FilmInfo {
            scene: "scenes/a b.toml".into(),
            scene_hash: "00ff".into(),
            seed: 7,
            frame: 3,
            samples: [16, 48],
            total: 64,
            window: [0, 0, 3, 2],
            backend: "cpu".into(),
            version: "0.1.0".into(),
            stats: vec![("seconds".into(), "1.5".into())],
        }
    }

    #[test]
    fn films_round_trip_exactly() {
        let dir = std::env::temp_dir().join(format!("ggx-film-file-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("part.exr");
        let mut film = Film::new(3, 2);
        film.add_window(
            [0, 0, 3, 2],
            &[sum(1.0, 4), sum(-1e-9, 1), sum(3e9, 9), sum(0.0, 0), sum(0.5, 2), sum(1e-17, 3)],
        )
        .unwrap();
        film.pixels_mut()[3].invalid = 0;
        film.pixels_mut()[4].add(Vec3::NAN);
        write_film(&path, &info(), &film, true, &OutputOptions::default()).unwrap();
        let (read_info, read) = read_film(&path, 6).unwrap();
        assert_eq!(read_info, info());
        assert_eq!(read_film_info(&path).unwrap(), (info(), [3, 2]));
        assert_eq!(read, film);
        // The RGB channels are the mean, for any viewer.
        let (w, h, rgb) = crate::read_exr(&path).unwrap();
        assert_eq!((w, h), (3, 2));
        assert_eq!(rgb[0], Vec3::splat(0.25));
        assert!(matches!(read_film(&path, 5), Err(OutputError::NotAFilm { .. })));
        // Without the film: an image with the header, which read_film refuses.
        write_film(&path, &info(), &film, false, &OutputOptions { exposure: 1.0, ..Default::default() }).unwrap();
        let msg = read_film(&path, 6).unwrap_err().to_string();
        assert!(msg.contains("holds no exact film"), "{msg}");
        assert_eq!(crate::read_exr(&path).unwrap().2[0], Vec3::splat(0.5), "exposed by one stop");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn bad_headers_name_the_field() {
        let mut attrs: HashMap<String, String> = info().attributes().into_iter().collect();
        assert_eq!(FilmInfo::parse(&attrs).unwrap(), info());
        attrs.insert("samples".into(), "9..3".into());
        assert_eq!(FilmInfo::parse(&attrs).unwrap_err(), "ggx.samples `9..3` is not a range A..B");
        attrs.insert("samples".into(), "0..3".into());
        attrs.insert("window".into(), "1,2,3".into());
        assert_eq!(FilmInfo::parse(&attrs).unwrap_err(), "ggx.window `1,2,3` is not x0,y0,x1,y1");
        attrs.insert("window".into(), "0,0,3,2".into());
        attrs.remove("seed");
        assert_eq!(FilmInfo::parse(&attrs).unwrap_err(), "the header lacks ggx.seed");
    }
}
