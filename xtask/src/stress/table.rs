//! Plain-text tables with aligned columns: the first column left-aligned, the rest right.

/// Renders `header` and `rows` (each as long as `header`) with two spaces between columns
/// and a rule under the header; widths count characters, not bytes.
pub fn render(header: &[&str], rows: &[Vec<String>]) -> String {
    let mut widths: Vec<usize> = header.iter().map(|h| h.chars().count()).collect();
    for row in rows {
        for (w, cell) in widths.iter_mut().zip(row) {
            *w = (*w).max(cell.chars().count());
        }
    }
    let line = |cells: &mut dyn Iterator<Item = &str>| {
        let mut out = String::new();
        for (i, (cell, &w)) in cells.zip(&widths).enumerate() {
            let pad = " ".repeat(w - cell.chars().count());
            match i {
                0 => out += &format!("{cell}{pad}"),
                _ => out += &format!("  {pad}{cell}"),
            }
        }
        out.trim_end().to_string() + "\n"
    };
    let mut out = line(&mut header.iter().copied());
    out += &"-".repeat(widths.iter().sum::<usize>() + 2 * (widths.len().saturating_sub(1)));
    out += "\n";
    for row in rows {
        out += &line(&mut row.iter().map(String::as_str));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_line_up() {
        let rows = vec![vec!["vndf".to_string(), "1".into()], vec!["x".into(), "12345".into()]];
        let t = render(&["method", "n"], &rows);
        assert_eq!(t, "method      n\n-------------\nvndf        1\nx       12345\n");
    }
}
