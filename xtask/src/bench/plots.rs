//! Log-log SVG plots of one scene's ladders with plotters' SVG backend (text is written as SVG
//! `<text>`, so no font files are needed): relMSE against render time and relMSE against spp,
//! one line per configuration, the legend beside the chart.

use super::configs::Axis;
use super::files::write_atomic;
use super::ladder::{Rung, Series};
use plotters::coord::CoordTranslate;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// Size of each SVG in pixels.
const SIZE: (u32, u32) = (1000, 600);
/// Width of the legend column on the right.
const LEGEND_WIDTH: u32 = 290;

/// Ten distinguishable colours (Tableau 10), one per configuration.
const COLORS: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// How a line is drawn: lines whose data can coincide with the baseline's (same images on
/// another backend or kernel) are dashed with open or cross markers, so that both stay visible.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Style {
    /// Solid line, filled dots.
    Solid,
    /// Dashed line, rings.
    DashedRing,
    /// Dashed line, crosses.
    DashedCross,
}

/// One line of a plot.
pub(crate) struct Line {
    /// Legend text.
    pub(crate) name: String,
    /// How it is drawn.
    pub(crate) style: Style,
    /// `(x, relMSE)` points.
    pub(crate) points: Vec<(f64, f64)>,
}

impl Line {
    /// The line of `series`: `(x(rung), relMSE)` per rung.
    fn of(series: &Series, x: &dyn Fn(&Rung) -> f64) -> Line {
        let style = match series.config.axis() {
            Axis::Backend => Style::DashedRing,
            Axis::Kernel => Style::DashedCross,
            _ => Style::Solid,
        };
        let points = series.rungs.iter().map(|r| (x(r), r.rel_mse)).collect();
        Line { name: series.config.name(), style, points }
    }
}

/// Draws `line`'s marker at `p` on any drawing area coordinate system.
fn marker<DB, C>(
    area: &DrawingArea<DB, C>,
    p: C::From,
    style: Style,
    color: RGBColor,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>>
where
    DB: DrawingBackend,
    C: CoordTranslate,
    C::From: Clone + 'static,
{
    match style {
        Style::Solid => area.draw(&Circle::new(p, 3, color.filled())),
        Style::DashedRing => area.draw(&Circle::new(p, 6, color.stroke_width(2))),
        Style::DashedCross => area.draw(&Cross::new(p, 5, color.stroke_width(2))),
    }
}

/// Writes `<scene>-relmse-vs-time.svg` and `<scene>-relmse-vs-spp.svg` into `dir`.
pub fn write(dir: &Path, scene: &str, series: &[Series]) -> Result<Vec<PathBuf>, String> {
    let lines = |x: &dyn Fn(&Rung) -> f64| -> Vec<Line> { series.iter().map(|s| Line::of(s, x)).collect() };
    let titles = [format!("{scene}: relMSE vs render time"), format!("{scene}: relMSE vs samples per pixel")];
    write_pair(dir, scene, &titles, "render time (s)", &lines(&|r| r.seconds), &lines(&|r| f64::from(r.spp)))
}

/// Writes the pair of plots of a scene, `<scene>-relmse-vs-time.svg` (x: `time_desc`, lines
/// `by_time`) and `<scene>-relmse-vs-spp.svg` (lines `by_spp`), titled `titles`.
pub(crate) fn write_pair(
    dir: &Path,
    scene: &str,
    titles: &[String; 2],
    time_desc: &str,
    by_time: &[Line],
    by_spp: &[Line],
) -> Result<Vec<PathBuf>, String> {
    let time = dir.join(format!("{scene}-relmse-vs-time.svg"));
    let spp = dir.join(format!("{scene}-relmse-vs-spp.svg"));
    write_atomic(&time, plot(&titles[0], time_desc, 10.0, by_time)?.as_bytes())?;
    write_atomic(&spp, plot(&titles[1], "samples per pixel", 2.0, by_spp)?.as_bytes())?;
    Ok(vec![time, spp])
}

/// `(lo, hi)` of the positive finite values, widened by 20 % on each side in log space terms.
fn log_bounds(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let (lo, hi) = values
        .filter(|v| *v > 0.0 && v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)));
    (lo <= hi).then_some((lo / 1.25, hi * 1.25))
}

/// A tick label: `1e-3` style for decades, plain for numbers that read well that way.
fn tick(v: f64) -> String {
    if (1.0..1e5).contains(&v) && v.fract() == 0.0 { format!("{v:.0}") } else { format!("{v:.0e}") }
}

/// The SVG of one log-log plot; `x_base` spaces the x axis's major ticks (10: decades, 2: the
/// spp ladder's powers of two).
pub(crate) fn plot(title: &str, x_desc: &str, x_base: f64, lines: &[Line]) -> Result<String, String> {
    let err = |e: &dyn std::fmt::Display| format!("plot `{title}`: {e}");
    let points = || lines.iter().flat_map(|l| l.points.iter().copied());
    let (x0, x1) = log_bounds(points().map(|p| p.0)).ok_or_else(|| err(&"no positive x values"))?;
    let (y0, y1) = log_bounds(points().map(|p| p.1)).ok_or_else(|| err(&"no positive relMSE values"))?;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(|e| err(&e))?;
        let (chart_area, legend_area) = root.split_horizontally(SIZE.0 - LEGEND_WIDTH);
        let mut chart = ChartBuilder::on(&chart_area)
            .caption(title, ("sans-serif", 20))
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(70)
            .build_cartesian_2d((x0..x1).log_scale().base(x_base), (y0..y1).log_scale())
            .map_err(|e| err(&e))?;
        chart
            .configure_mesh()
            .x_desc(x_desc)
            .y_desc("relMSE")
            .x_label_formatter(&|v| tick(*v))
            .y_label_formatter(&|v| tick(*v))
            .draw()
            .map_err(|e| err(&e))?;
        for (i, line) in lines.iter().enumerate() {
            let color = COLORS[i % COLORS.len()];
            let valid: Vec<(f64, f64)> = line
                .points
                .iter()
                .copied()
                .filter(|&(x, y)| x > 0.0 && y > 0.0 && x.is_finite() && y.is_finite())
                .collect();
            if line.style == Style::Solid {
                chart.draw_series(LineSeries::new(valid.clone(), color.stroke_width(2))).map_err(|e| err(&e))?;
            } else {
                chart
                    .draw_series(DashedLineSeries::new(valid.clone(), 8, 5, color.stroke_width(2)))
                    .map_err(|e| err(&e))?;
            }
            let area = chart.plotting_area();
            for &p in &valid {
                marker(area, p, line.style, color).map_err(|e| err(&e))?;
            }
            let y = 50 + 24 * i as i32;
            legend_area.draw(&PathElement::new(vec![(10, y), (40, y)], color.stroke_width(3))).map_err(|e| err(&e))?;
            marker(&legend_area, (25, y), line.style, color).map_err(|e| err(&e))?;
            legend_area
                .draw(&Text::new(line.name.clone(), (48, y - 7), ("sans-serif", 14).into_font()))
                .map_err(|e| err(&e))?;
        }
        root.present().map_err(|e| err(&e))?;
    }
    Ok(svg)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn svg_has_axes_and_legend() {
        let lines = vec![
            Line {
                name: "vndf-mis-sobol-cpu-spec".into(),
                style: Style::Solid,
                points: vec![(1.0, 0.1), (2.0, 0.05), (4.0, 0.02)],
            },
            Line {
                name: "cosine-mis-sobol-cpu-spec".into(),
                style: Style::DashedRing,
                points: vec![(1.0, 0.5), (2.0, 0.0), (4.0, 0.1)],
            },
            Line { name: "vndf-mis-sobol-cpu-generic".into(), style: Style::DashedCross, points: vec![(1.0, 0.1)] },
        ];
        let svg = plot("t: relMSE vs spp", "samples per pixel", 2.0, &lines).unwrap();
        assert!(svg.starts_with("<svg"), "{}", &svg[..40]);
        for text in ["t: relMSE vs spp", "samples per pixel", "relMSE", "vndf-mis-sobol-cpu-spec", "cosine-mis-sobol"] {
            assert!(svg.contains(text), "missing {text}");
        }
        let empty = Line { name: "a".into(), style: Style::Solid, points: vec![(0.0, 1.0)] };
        assert!(plot("empty", "x", 10.0, &[empty]).is_err());
    }

    #[test]
    fn ticks_and_bounds() {
        assert_eq!(tick(16.0), "16");
        assert_eq!(tick(0.001), "1e-3");
        assert_eq!(tick(0.5), "5e-1");
        assert_eq!(log_bounds([2.0, 0.0, 8.0, f64::NAN].into_iter()), Some((1.6, 10.0)));
        assert_eq!(log_bounds([0.0].into_iter()), None);
    }
}
