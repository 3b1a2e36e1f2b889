//! Output names of animation frames: runs of `#` in the file name are the frame number.

use std::path::{Path, PathBuf};

use anyhow::{Result, bail};

/// `template` with its last run of `#` replaced by `frame`, zero-padded to the run's length
/// (`turntable-####.png`, frame 7: `turntable-0007.png`); `template` itself for `None` (a
/// single image). Only the file name is searched, so directories may contain `#`.
pub fn output_path(template: &Path, frame: Option<u32>) -> Result<PathBuf> {
    let Some(frame) = frame else { return Ok(template.to_owned()) };
    let name = template.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let Some(end) = name.rfind('#').map(|i| i + 1) else {
        bail!(
            "{}: with --frames the file name needs `#` for the frame number, e.g. frame-####.png",
            template.display()
        );
    };
    let start = name[..end].trim_end_matches('#').len();
    let named = format!("{}{frame:0width$}{}", &name[..start], &name[end..], width = end - start);
    Ok(template.with_file_name(named))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hashes_become_the_padded_frame() {
        let p = |t: &str, f| output_path(Path::new(t), f).map(|p| p.display().to_string());
        assert_eq!(p("out/t-####.png", Some(7)).unwrap(), "out/t-0007.png");
        assert_eq!(p("a#/t_#.exr", Some(12345)).unwrap(), "a#/t_12345.exr");
        assert_eq!(p("##-x-##.png", Some(3)).unwrap(), "##-x-03.png");
        assert_eq!(p("plain.png", None).unwrap(), "plain.png");
        let msg = p("plain.png", Some(1)).unwrap_err().to_string();
        assert!(msg.contains("needs `#`"), "{msg}");
    }
}
