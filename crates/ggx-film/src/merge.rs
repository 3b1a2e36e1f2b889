//! [`merge_films`]: adds film files that rendered disjoint samples of one scene into the film of
//! their union, after checking that they can be added, and says what is missing.

use crate::{Film, FilmInfo, Window};

/// A film to merge, with the name of the file it came from (for messages).
pub struct Part {
    /// The file name, as the user gave it.
    pub name: String,
    /// What the file says about its render.
    pub info: FilmInfo,
    /// Its samples.
    pub film: Film,
}

/// The union of the parts.
pub struct Merged {
    /// Identity of the union: the parts' scene, with the sample range `[A, B)` from the
    /// smallest start to the largest end and the bounding box of their windows.
    pub info: FilmInfo,
    /// The sum of the parts.
    pub film: Film,
    /// What the union lacks, one line each (empty when every pixel of the window holds every
    /// sample of the range).
    pub missing: Vec<String>,
    /// Whether each pixel's samples are one run from the range's start (so the film can be
    /// written, resumed and merged again even when incomplete).
    pub contiguous: bool,
}

/// Tile edge used to report missing pixels.
const TILE: u32 = 16;

/// Most tiles listed in a report.
const MAX_TILES_LISTED: usize = 8;

/// Checks that the parts come from the same scene, seed, frame, size, backend and version and
/// that no two hold the same sample of a pixel, then adds them. The sum is exact, so it equals
/// a single render of the union bit for bit, whatever the split.
pub fn merge_films(mut parts: Vec<Part>) -> Result<Merged, String> {
    let first = parts.first().ok_or("no films to merge")?;
    let (size, reference) = ([first.film.width(), first.film.height()], first.info.clone());
    let first_name = first.name.clone();
    for part in &parts {
        let differ = |what: &str, theirs: &dyn std::fmt::Display, ours: &dyn std::fmt::Display| {
            format!("{}: {what} {theirs}, but {first_name} has {ours}", part.name)
        };
        let info = &part.info;
        let part_size = [part.film.width(), part.film.height()];
        if part_size != size {
            let show = |[w, h]: [u32; 2]| format!("{w}x{h}");
            return Err(differ("is", &show(part_size), &show(size)));
        }
        if info.scene_hash != reference.scene_hash {
            return Err(format!(
                "{}: rendered another scene (or the same file with other settings) than {first_name}: scene hash {} against {}",
                part.name, info.scene_hash, reference.scene_hash
            ));
        }
        for (what, theirs, ours) in [
            ("has seed", info.seed.to_string(), reference.seed.to_string()),
            ("is frame", info.frame.to_string(), reference.frame.to_string()),
            ("was rendered on the backend", info.backend.clone(), reference.backend.clone()),
            ("was rendered by ggx", info.version.clone(), reference.version.clone()),
        ] {
            if theirs != ours {
                return Err(differ(what, &theirs, &ours));
            }
        }
        let [a, b] = info.samples;
        if let Some(i) = part.film.pixels().iter().position(|p| p.samples > b - a) {
            return Err(format!(
                "{}: pixel {i} holds {} samples, more than its range {a}..{b}",
                part.name,
                part.film.pixels()[i].samples
            ));
        }
    }
    parts.sort_by_key(|p| p.info.samples);
    let start = parts.iter().map(|p| p.info.samples[0]).min().unwrap_or(0);
    let end = parts.iter().map(|p| p.info.samples[1]).max().unwrap_or(0);
    let window = bounding_window(parts.iter().map(|p| p.info.window));
    let [width, _] = size;

    // Per pixel, walk the parts in order of their start: an interval that begins before the
    // previous one ended is an overlap; one that begins after it is a gap.
    let mut film = Film::try_new(size[0], size[1]).map_err(|e| e.to_string())?;
    let mut short: Vec<(u32, u32, u32, u32)> = Vec::new(); // (x, y, first missing, last missing end)
    let mut contiguous = true;
    for (i, acc) in film.pixels_mut().iter_mut().enumerate() {
        let (x, y) = ((i % width as usize) as u32, (i / width as usize) as u32);
        let inside = x >= window[0] && x < window[2] && y >= window[1] && y < window[3];
        let (mut cursor, mut owner, mut gap): (u32, Option<&str>, Option<u32>) = (start, None, None);
        for part in &parts {
            let p = &part.film.pixels()[i];
            if p.samples == 0 {
                continue;
            }
            let (a, b) = (part.info.samples[0], part.info.samples[0] + p.samples);
            if a < cursor && owner.is_some() {
                return Err(format!(
                    "{} and {} both hold samples {a}..{} of pixel ({x}, {y}): their ranges overlap",
                    owner.unwrap_or_default(),
                    part.name,
                    cursor.min(b)
                ));
            }
            if a > cursor {
                gap.get_or_insert(cursor);
                contiguous = false;
            }
            // Counts were checked against u32 ranges, so the sum fits.
            if acc.merge(p).is_none() {
                return Err(format!("{}: pixel ({x}, {y}) would hold more than {} samples", part.name, u32::MAX));
            }
            (cursor, owner) = (b, Some(part.name.as_str()));
        }
        if inside && (gap.is_some() || cursor < end) {
            short.push((x, y, gap.unwrap_or(cursor), end));
        }
    }
    let missing = describe_missing(&parts, [start, end], window, &short);
    let stats = Vec::new();
    let info = FilmInfo { samples: [start, end], window, stats, ..reference };
    Ok(Merged { info, film, missing, contiguous })
}

/// The smallest window holding all of `windows`.
fn bounding_window(windows: impl Iterator<Item = Window>) -> Window {
    windows.reduce(|a, b| [a[0].min(b[0]), a[1].min(b[1]), a[2].max(b[2]), a[3].max(b[3])]).unwrap_or_default()
}

/// Lines naming the sample ranges no part asked for and the tiles whose pixels lack samples.
fn describe_missing(
    parts: &[Part],
    [start, end]: [u32; 2],
    window: Window,
    short: &[(u32, u32, u32, u32)],
) -> Vec<String> {
    let mut lines = Vec::new();
    let mut cursor = start;
    for part in parts {
        let [a, b] = part.info.samples;
        if a > cursor {
            lines.push(format!("samples {cursor}..{a}: no part was rendered for them"));
        }
        cursor = cursor.max(b);
    }
    if short.is_empty() {
        return lines;
    }
    let pixels = u64::from(window[2] - window[0]) * u64::from(window[3] - window[1]);
    lines.push(format!("{} of {pixels} pixels lack samples of {start}..{end}", short.len()));
    let mut tiles: Vec<((u32, u32), u32)> = Vec::new();
    for &(x, y, from, _) in short {
        let key = (x / TILE, y / TILE);
        match tiles.iter_mut().find(|(k, _)| *k == key) {
            Some((_, first)) => *first = (*first).min(from),
            None => tiles.push((key, from)),
        }
    }
    for &((tx, ty), from) in tiles.iter().take(MAX_TILES_LISTED) {
        let (x0, y0) = (tx * TILE, ty * TILE);
        lines.push(format!("  tile ({x0}, {y0})-({}, {}): samples from {from} on", x0 + TILE, y0 + TILE));
    }
    if tiles.len() > MAX_TILES_LISTED {
        lines.push(format!("  and {} more tiles", tiles.len() - MAX_TILES_LISTED));
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::SampleSum;
    use glam::Vec3;

    /// A 4x2 film of samples `[a, b)` where sample `s` of pixel `i` is `f(i, s)`.
    fn part(name: &str, [a, b]: [u32; 2], hash: &str) -> Part {
        let mut film = Film::new(4, 2);
        for (i, p) in film.pixels_mut().iter_mut().enumerate() {
            for s in a..b {
                p.add(Vec3::new((i as f32 + 1.0) / (s as f32 + 3.0), (s as f32).sqrt(), 1e-7 * s as f32));
            }
        }
        let info = FilmInfo {
            scene_hash: hash.into(),
            samples: [a, b],
            window: [0, 0, 4, 2],
            backend: "cpu".into(),
            ..Default::default()
        };
        Part { name: name.into(), info, film }
    }

    #[test]
    fn any_split_merges_to_the_whole_bit_for_bit() {
        let whole = part("whole", [0, 37], "h").film;
        for splits in [vec![0, 37], vec![0, 1, 37], vec![0, 16, 17, 32, 37]] {
            let parts: Vec<Part> =
                splits.windows(2).rev().enumerate().map(|(k, w)| part(&format!("p{k}"), [w[0], w[1]], "h")).collect();
            let merged = merge_films(parts).unwrap();
            assert_eq!(merged.film, whole, "{splits:?}");
            assert!(merged.missing.is_empty() && merged.contiguous);
            assert_eq!((merged.info.samples, merged.info.window), ([0, 37], [0, 0, 4, 2]));
        }
    }

    #[test]
    fn overlaps_and_strangers_are_refused() {
        let msg = merge_films(vec![part("a", [0, 10], "h"), part("b", [8, 20], "h")]).err().unwrap();
        assert_eq!(msg, "a and b both hold samples 8..10 of pixel (0, 0): their ranges overlap");
        let msg = merge_films(vec![part("a", [0, 10], "h"), part("b", [10, 20], "other")]).err().unwrap();
        assert!(msg.starts_with("b: rendered another scene") && msg.contains("other against h"), "{msg}");
        let mut seeded = part("b", [10, 20], "h");
        seeded.info.seed = 9;
        let msg = merge_films(vec![part("a", [0, 10], "h"), seeded]).err().unwrap();
        assert_eq!(msg, "b: has seed 9, but a has 0");
        assert_eq!(merge_films(vec![]).err().unwrap(), "no films to merge");
    }

    #[test]
    fn missing_ranges_and_tiles_are_named() {
        let merged = merge_films(vec![part("a", [0, 8], "h"), part("c", [16, 24], "h")]).unwrap();
        assert!(!merged.contiguous);
        assert_eq!(merged.missing[0], "samples 8..16: no part was rendered for them");
        assert_eq!(merged.missing[1], "8 of 8 pixels lack samples of 0..24");
        assert_eq!(merged.missing[2], "  tile (0, 0)-(16, 16): samples from 8 on");
        // An interrupted part: its last pixel stopped early; the union is still one run.
        let mut cut = part("b", [8, 16], "h");
        cut.film.pixels_mut()[7] = SampleSum::default();
        let merged = merge_films(vec![part("a", [0, 8], "h"), cut]).unwrap();
        assert!(merged.contiguous);
        assert_eq!(
            merged.missing,
            ["1 of 8 pixels lack samples of 0..16", "  tile (0, 0)-(16, 16): samples from 8 on"]
        );
    }
}
