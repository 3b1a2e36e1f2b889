//! OBJ face indices checked before `tobj` resolves them: `tobj` turns an index into a
//! `usize` (`x - 1`, or `count + x` for a relative one) and multiplies it without an overflow
//! check, so an index far out of range would overflow (a panic in a debug build, a wrong
//! index in a release one) instead of being refused.

/// The element kinds a face vertex `v/vt/vn` refers to, in that order, with their keywords.
const KINDS: [(&str, &str); 3] = [("v", "position"), ("vt", "texture coordinate"), ("vn", "normal")];

/// Checks every index of every `f` and `l` line of `text`: an absolute index must lie in
/// `1..=N` (`N`: that kind's lines in the whole file), a relative one in `-n..=-1` (`n`:
/// that kind's lines before the face). Errors name the line (1-based), the vertex and the
/// index. Parts that are not integers are left to `tobj`, which refuses them.
pub(crate) fn check_face_indices(text: &str) -> Result<(), String> {
    let mut total = [0u64; 3];
    for line in text.lines() {
        if let Some(k) = kind_of(line) {
            total[k] += 1;
        }
    }
    let mut seen = [0u64; 3];
    for (number, line) in text.lines().enumerate() {
        if let Some(k) = kind_of(line) {
            seen[k] += 1;
            continue;
        }
        let mut words = line.split_whitespace();
        if !matches!(words.next(), Some("f" | "l")) {
            continue;
        }
        for (vertex, word) in words.enumerate() {
            for (k, part) in word.split('/').enumerate().take(3) {
                let Ok(index) = part.parse::<i64>() else { continue };
                let in_range = if index < 0 {
                    index.unsigned_abs() <= seen[k]
                } else {
                    index >= 1 && index.unsigned_abs() <= total[k]
                };
                if !in_range {
                    let (keyword, what) = KINDS[k];
                    let range = if index < 0 { format!("-{}..=-1 here", seen[k]) } else { format!("1..={}", total[k]) };
                    return Err(format!(
                        "line {}: vertex {} refers to {what} {index}, outside the `{keyword}` lines ({range})",
                        number + 1,
                        vertex + 1
                    ));
                }
            }
        }
    }
    Ok(())
}

/// Which of [`KINDS`] a line defines, by its first word.
fn kind_of(line: &str) -> Option<usize> {
    let first = line.split_whitespace().next()?;
    KINDS.iter().position(|&(keyword, _)| keyword == first)
}

#[cfg(test)]
mod tests {
    use super::check_face_indices;

    const MESH: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n";

    #[test]
    fn indices_in_range_pass() {
        for face in ["f 1 2 3", "f -3 -2 -1", "f 1/1/1 2/1/1 3/-1/-1", "f 1//1 2//1 3//1", "l 1 2"] {
            assert_eq!(check_face_indices(&format!("{MESH}{face}\n")), Ok(()), "{face}");
        }
    }

    #[test]
    fn indices_out_of_range_name_the_line_and_vertex() {
        let cases = [
            ("f 1 2 4", "line 6: vertex 3 refers to position 4, outside the `v` lines (1..=3)"),
            ("f 0 1 2", "line 6: vertex 1 refers to position 0"),
            ("f 1/2 2/1 3/1", "line 6: vertex 1 refers to texture coordinate 2, outside the `vt` lines (1..=1)"),
            ("f 1//1 2//1 3//9223372036854775807", "line 6: vertex 3 refers to normal 9223372036854775807"),
            ("f -4 -2 -1", "line 6: vertex 1 refers to position -4, outside the `v` lines (-3..=-1 here)"),
            ("f 1//-2 2//1 3//1", "refers to normal -2"),
            ("f 1//-9223372036854775808 2 3", "refers to normal -9223372036854775808"),
        ];
        for (face, expected) in cases {
            let err = check_face_indices(&format!("{MESH}{face}\n")).unwrap_err();
            assert!(err.starts_with(expected) || err.contains(expected), "{face}: {err}");
        }
    }

    /// A relative index counts only the lines above its face.
    #[test]
    fn relative_indices_count_the_lines_before_the_face() {
        assert!(check_face_indices("v 0 0 0\nf -1 -2 -1\nv 1 0 0\n").is_err());
        assert_eq!(check_face_indices("v 0 0 0\nv 1 0 0\nf -1 -2 -1\n"), Ok(()));
    }
}
