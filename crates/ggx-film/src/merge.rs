//! [`Merger`]: adds film files that rendered disjoint samples of one scene into the film of
//! their union, one part at a time (so memory holds the sum and one part, never all of them),
//! after checking that they can be added, and says what is missing.

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
    /// smallest start to the largest end present and the bounding box of their windows.
    pub info: FilmInfo,
    /// The sum of the parts.
    pub film: Film,
    /// What the union lacks of the whole render (samples `[0, total)` of every pixel), one
    /// line each; empty when nothing is missing.
    pub missing: Vec<String>,
    /// Whether each pixel's samples are one run from the range's start (so the film can be
    /// written, resumed and merged again even when incomplete).
    pub contiguous: bool,
}

/// Tile edge used to report missing pixels.
const TILE: u32 = 16;

/// Most tiles listed in a report.
const MAX_TILES_LISTED: usize = 8;

/// Adds parts in order of their range start. Per pixel it keeps where the samples added so
/// far end and which part added the last ones, so an overlap is found at once and a gap
/// remembered: 16 bytes per pixel beside the sum.
pub struct Merger {
    reference: (String, FilmInfo, [u32; 2]),
    film: Film,
    /// Per pixel: the end of its samples so far (`u32::MAX` before the first).
    cursor: Vec<u32>,
    /// Per pixel: the first sample it holds (`u32::MAX` before the first).
    begin: Vec<u32>,
    /// Per pixel: the first missing sample of a gap, `u32::MAX` while there is none.
    gap: Vec<u32>,
    /// Per pixel: the index in `names` of the part that added its last samples.
    owner: Vec<u32>,
    names: Vec<String>,
    /// Requested ranges seen, in order of their start.
    ranges: Vec<[u32; 2]>,
    windows: Vec<Window>,
}

impl Merger {
    /// A merger for parts like `first` (its name, header and `[width, height]`).
    pub fn new(name: &str, info: &FilmInfo, size: [u32; 2]) -> Result<Merger, String> {
        let film = Film::try_new(size[0], size[1]).map_err(|e| e.to_string())?;
        let n = film.len();
        let filled = |v: u32| -> Result<Vec<u32>, String> {
            let mut out = Vec::new();
            out.try_reserve_exact(n)
                .map_err(|_| format!("cannot allocate the merge of {}x{} pixels", size[0], size[1]))?;
            out.resize(n, v);
            Ok(out)
        };
        Ok(Merger {
            reference: (name.to_owned(), info.clone(), size),
            film,
            cursor: filled(u32::MAX)?,
            begin: filled(u32::MAX)?,
            gap: filled(u32::MAX)?,
            owner: filled(0)?,
            names: Vec::new(),
            ranges: Vec::new(),
            windows: Vec::new(),
        })
    }

    /// Checks that a part (its header and size) can be added to the others: same scene hash,
    /// seed, frame, backend (with its acceleration structure or adapter), version and size.
    pub fn check(&self, name: &str, info: &FilmInfo, size: [u32; 2]) -> Result<(), String> {
        let (first_name, reference, ref_size) = &self.reference;
        let differ = |what: &str, theirs: &dyn std::fmt::Display, ours: &dyn std::fmt::Display| {
            format!("{name}: {what} {theirs}, but {first_name} has {ours}")
        };
        if size != *ref_size {
            let show = |[w, h]: [u32; 2]| format!("{w}x{h}");
            return Err(differ("is", &show(size), &show(*ref_size)));
        }
        if info.scene_hash != reference.scene_hash {
            return Err(format!(
                "{name}: rendered another scene (or the same file with other settings) than {first_name}: scene hash {} against {}",
                info.scene_hash, reference.scene_hash
            ));
        }
        for (what, theirs, ours) in [
            ("has seed", info.seed.to_string(), reference.seed.to_string()),
            ("is frame", info.frame.to_string(), reference.frame.to_string()),
            ("was rendered on", info.backend.clone(), reference.backend.clone()),
            ("was rendered by ggx", info.version.clone(), reference.version.clone()),
        ] {
            if theirs != ours {
                return Err(differ(what, &theirs, &ours));
            }
        }
        Ok(())
    }

    /// Adds a part; parts must come in order of their range start (`info.samples[0]`).
    pub fn add(&mut self, part: &Part) -> Result<(), String> {
        self.check(&part.name, &part.info, [part.film.width(), part.film.height()])?;
        let [a, b] = part.info.samples;
        if self.ranges.last().is_some_and(|r| r[0] > a) {
            return Err(format!("{}: parts must be added in order of their first sample", part.name));
        }
        if let Some(i) = part.film.pixels().iter().position(|p| p.samples > b.saturating_sub(a)) {
            let held = part.film.pixels()[i].samples;
            return Err(format!("{}: pixel {i} holds {held} samples, more than its range {a}..{b}", part.name));
        }
        let index = u32::try_from(self.names.len()).map_err(|_| "too many parts".to_owned())?;
        let width = part.film.width() as usize;
        for (i, p) in part.film.pixels().iter().enumerate() {
            if p.samples == 0 {
                continue;
            }
            let end = a + p.samples;
            let cursor = self.cursor[i];
            if cursor != u32::MAX && a < cursor {
                let (x, y) = (i % width, i / width);
                let other = self.names.get(self.owner[i] as usize).map_or("another part", String::as_str);
                return Err(format!(
                    "{other} and {} both hold samples {a}..{} of pixel ({x}, {y}): their ranges overlap",
                    part.name,
                    cursor.min(end)
                ));
            }
            if cursor != u32::MAX && a > cursor && self.gap[i] == u32::MAX {
                self.gap[i] = cursor;
            }
            if self.film.pixels_mut()[i].merge(p).is_none() {
                return Err(format!("{}: a pixel would hold more than {} samples", part.name, u32::MAX));
            }
            self.cursor[i] = end;
            self.begin[i] = self.begin[i].min(a);
            self.owner[i] = index;
        }
        self.names.push(part.name.clone());
        self.ranges.push(part.info.samples);
        self.windows.push(part.info.window);
        Ok(())
    }

    /// The union, and what it lacks of samples `[0, total)` of every pixel, where `total` is
    /// the largest whole-render sample count the parts name (a missing first or last part,
    /// or a missing window, is reported, not mistaken for a smaller render).
    pub fn finish(self) -> Merged {
        let [width, height] = self.reference.2;
        let start = self.ranges.iter().map(|r| r[0]).min().unwrap_or(0);
        let end = self.ranges.iter().map(|r| r[1]).max().unwrap_or(0);
        let total = self.reference.1.total.max(end);
        let contiguous =
            self.gap.iter().all(|&g| g == u32::MAX) && self.begin.iter().all(|&b| b == u32::MAX || b == start);
        // Per pixel: the first sample it lacks of [0, total), if any.
        let short: Vec<(u32, u32, u32)> = (0..self.cursor.len())
            .filter_map(|i| {
                let (x, y) = ((i % width as usize) as u32, (i / width as usize) as u32);
                let held = self.film.pixels()[i].samples;
                let first = if held == 0 || self.begin[i] > 0 {
                    0
                } else if self.gap[i] != u32::MAX {
                    self.gap[i]
                } else if self.cursor[i] < total {
                    self.cursor[i]
                } else {
                    return None;
                };
                Some((x, y, first))
            })
            .collect();
        let missing = describe_missing(&self.ranges, total, [width, height], &short);
        let window = bounding_window(self.windows.iter().copied());
        let info = FilmInfo { samples: [start, end], window, stats: Vec::new(), ..self.reference.1 };
        Merged { info, film: self.film, missing, contiguous }
    }
}

/// Merges films held in memory (sorted here by their range start): [`Merger`] for tests and
/// small jobs. The sum is exact, so it equals a single render of the union bit for bit.
pub fn merge_films(mut parts: Vec<Part>) -> Result<Merged, String> {
    parts.sort_by_key(|p| p.info.samples);
    let first = parts.first().ok_or("no films to merge")?;
    let mut merger = Merger::new(&first.name, &first.info, [first.film.width(), first.film.height()])?;
    for part in &parts {
        merger.add(part)?;
    }
    Ok(merger.finish())
}

/// The smallest window holding all of `windows`.
fn bounding_window(windows: impl Iterator<Item = Window>) -> Window {
    windows.reduce(|a, b| [a[0].min(b[0]), a[1].min(b[1]), a[2].max(b[2]), a[3].max(b[3])]).unwrap_or_default()
}

/// Lines naming the sample ranges of `[0, total)` that no part asked for and the tiles whose
/// pixels lack samples (`short`: pixel and its first missing sample).
fn describe_missing(
    ranges: &[[u32; 2]],
    total: u32,
    [width, height]: [u32; 2],
    short: &[(u32, u32, u32)],
) -> Vec<String> {
    let mut lines = Vec::new();
    let mut cursor = 0;
    for &[a, b] in ranges {
        if a > cursor {
            lines.push(format!("samples {cursor}..{a}: no part was rendered for them"));
        }
        cursor = cursor.max(b);
    }
    if cursor < total {
        lines.push(format!("samples {cursor}..{total}: no part was rendered for them"));
    }
    if short.is_empty() {
        return lines;
    }
    let pixels = u64::from(width) * u64::from(height);
    lines.push(format!("{} of {pixels} pixels lack samples of 0..{total}", short.len()));
    let mut tiles: Vec<((u32, u32), u32)> = Vec::new();
    for &(x, y, from) in short {
        let key = (x / TILE, y / TILE);
        match tiles.iter_mut().find(|(k, _)| *k == key) {
            Some((_, first)) => *first = (*first).min(from),
            None => tiles.push((key, from)),
        }
    }
    for &((tx, ty), from) in tiles.iter().take(MAX_TILES_LISTED) {
        let (x0, y0) = (tx * TILE, ty * TILE);
        let (x1, y1) = ((x0 + TILE).min(width), (y0 + TILE).min(height));
        lines.push(format!("  tile ({x0}, {y0})-({x1}, {y1}): samples from {from} on"));
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

    /// A 4x2 film of samples `[a, b)` of a 24-sample render where sample `s` of pixel `i` is
    /// `f(i, s)`.
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
            total: 24,
            window: [0, 0, 4, 2],
            backend: "cpu".into(),
            ..Default::default()
        };
        Part { name: name.into(), info, film }
    }

    #[test]
    fn any_split_merges_to_the_whole_bit_for_bit() {
        let whole = part("whole", [0, 24], "h").film;
        for splits in [vec![0, 24], vec![0, 1, 24], vec![0, 16, 17, 23, 24]] {
            let parts: Vec<Part> =
                splits.windows(2).rev().enumerate().map(|(k, w)| part(&format!("p{k}"), [w[0], w[1]], "h")).collect();
            let merged = merge_films(parts).unwrap();
            assert_eq!(merged.film, whole, "{splits:?}");
            assert!(merged.missing.is_empty() && merged.contiguous, "{:?}", merged.missing);
            assert_eq!((merged.info.samples, merged.info.window), ([0, 24], [0, 0, 4, 2]));
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
        let mut bvh2 = part("b", [10, 20], "h");
        bvh2.info.backend = "cpu bvh2".into();
        assert!(merge_films(vec![part("a", [0, 10], "h"), bvh2]).err().unwrap().contains("was rendered on cpu bvh2"));
        assert_eq!(merge_films(vec![]).err().unwrap(), "no films to merge");
    }

    #[test]
    fn missing_ranges_and_tiles_are_named() {
        let merged = merge_films(vec![part("a", [0, 8], "h"), part("c", [16, 24], "h")]).unwrap();
        assert!(!merged.contiguous);
        assert_eq!(merged.missing[0], "samples 8..16: no part was rendered for them");
        assert_eq!(merged.missing[1], "8 of 8 pixels lack samples of 0..24");
        assert_eq!(merged.missing[2], "  tile (0, 0)-(4, 2): samples from 8 on");
        // An interrupted part: its last pixel stopped early; the union is still one run.
        let mut cut = part("b", [8, 24], "h");
        cut.film.pixels_mut()[7] = SampleSum::default();
        let merged = merge_films(vec![part("a", [0, 8], "h"), cut]).unwrap();
        assert!(merged.contiguous);
        assert_eq!(merged.missing, ["1 of 8 pixels lack samples of 0..24", "  tile (0, 0)-(4, 2): samples from 8 on"]);
    }

    #[test]
    fn a_missing_first_or_last_part_is_missing() {
        let merged = merge_films(vec![part("b", [8, 16], "h"), part("c", [16, 24], "h")]).unwrap();
        assert_eq!(merged.missing[0], "samples 0..8: no part was rendered for them");
        assert!(merged.contiguous, "one run from 8: an incomplete film can still be written");
        assert_eq!(merged.info.samples, [8, 24]);
        let merged = merge_films(vec![part("a", [0, 8], "h"), part("b", [8, 16], "h")]).unwrap();
        assert_eq!(merged.missing[0], "samples 16..24: no part was rendered for them");
        // A missing window: the other pixels lack everything.
        let mut left = part("l", [0, 24], "h");
        left.info.window = [0, 0, 2, 2];
        for (i, p) in left.film.pixels_mut().iter_mut().enumerate() {
            if i % 4 >= 2 {
                *p = SampleSum::default();
            }
        }
        let merged = merge_films(vec![left]).unwrap();
        assert_eq!(merged.missing, ["4 of 8 pixels lack samples of 0..24", "  tile (0, 0)-(4, 2): samples from 0 on"]);
    }
}
