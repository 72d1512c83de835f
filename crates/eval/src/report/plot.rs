//! The campaign's PNG plots ([`write_plots`]): RMSE, NEES and per-axis error curves on
//! logarithmic axes, drawn with plotters.

use super::fmt_trim;
use crate::metrics::{chi2_mean_bounds, rmse_axes, rmse_pos, rmse_vel};
use crate::results::McResult;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::collections::BTreeSet;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// Font used for the text in the plots.
pub const FONT_PATH: &str = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

/// Size of the single-panel plots \[px\].
const PLOT_SIZE: (u32, u32) = (1000, 600);

/// Size of the three-panel per-axis plot \[px\].
const AXES_PLOT_SIZE: (u32, u32) = (1000, 900);

/// Line colours of the first filters, in scenario order: matplotlib's tab10 without its
/// gray, then five more of clearly different hue (black and gray are reserved for the
/// PCRLB and the NEES bands). Later filters get generated colours ([`color_of`]).
const COLORS: [RGBColor; 14] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(23, 190, 207),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(188, 189, 34),
    RGBColor(0, 0, 128),
    RGBColor(128, 0, 0),
    RGBColor(0, 128, 128),
    RGBColor(255, 0, 255),
    RGBColor(230, 171, 2),
];

/// Registers DejaVu Sans as plotters' "sans-serif" once per process; the error says
/// which file and package are missing.
fn ensure_font() -> Result<(), String> {
    static FONT: OnceLock<Result<(), String>> = OnceLock::new();
    FONT.get_or_init(|| {
        let bytes = std::fs::read(FONT_PATH).map_err(|e| {
            format!(
                "cannot draw plots: font {FONT_PATH} not readable ({e}); install the Debian \
                 package fonts-dejavu-core"
            )
        })?;
        let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
        plotters::style::register_font("sans-serif", FontStyle::Normal, bytes)
            .map_err(|_| format!("cannot draw plots: {FONT_PATH} is not a valid font"))
    })
    .clone()
}

/// One line of a plot.
struct Curve {
    label: String,
    color: RGBColor,
    dashed: bool,
    points: Vec<(f64, f64)>,
}

impl Curve {
    fn new(label: &str, color: RGBColor, dashed: bool, t: &[f64], y: &[f64]) -> Self {
        Curve {
            label: label.to_string(),
            color,
            dashed,
            points: t.iter().copied().zip(y.iter().copied()).collect(),
        }
    }

    /// Runs of consecutive points drawable on a log y-axis (finite, y > 0).
    fn segments(&self) -> Vec<Vec<(f64, f64)>> {
        let mut out = Vec::new();
        let mut cur = Vec::new();
        for &(x, y) in &self.points {
            if x.is_finite() && y.is_finite() && y > 0.0 {
                cur.push((x, y));
            } else if !cur.is_empty() {
                out.push(std::mem::take(&mut cur));
            }
        }
        if !cur.is_empty() {
            out.push(cur);
        }
        out
    }
}

/// The colour of filter `i`: every filter its own. The palette first; beyond it hues
/// stepped by the golden angle (137.5 degrees, so no two coincide) at three lightness
/// levels, fully saturated (never black or gray).
pub(super) fn color_of(i: usize) -> RGBColor {
    if let Some(c) = COLORS.get(i) {
        return *c;
    }
    let k = i - COLORS.len();
    let hue = (20.0 + k as f64 * 137.507_764_050_037_85).rem_euclid(360.0);
    let lightness = [0.35, 0.55, 0.7][k % 3];
    hsl_to_rgb(hue, 1.0, lightness)
}

/// HSL (hue in degrees, saturation and lightness in [0, 1]) to 8-bit RGB.
fn hsl_to_rgb(h: f64, s: f64, l: f64) -> RGBColor {
    let c = (1.0 - (2.0 * l - 1.0).abs()) * s;
    let hp = h / 60.0;
    let x = c * (1.0 - (hp.rem_euclid(2.0) - 1.0).abs());
    let (r, g, b) = match hp as u32 {
        0 => (c, x, 0.0),
        1 => (x, c, 0.0),
        2 => (0.0, c, x),
        3 => (0.0, x, c),
        4 => (x, 0.0, c),
        _ => (c, 0.0, x),
    };
    let m = l - c / 2.0;
    let to8 = |v: f64| ((v + m) * 255.0).round().clamp(0.0, 255.0) as u8;
    RGBColor(to8(r), to8(g), to8(b))
}

/// Time axis range: the finite times (a unit range around a single time).
fn time_range(t: &[f64]) -> Result<Range<f64>, String> {
    let (lo, hi) = t
        .iter()
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    if !lo.is_finite() {
        return Err("cannot draw plots: no finite times".to_string());
    }
    Ok(if hi > lo { lo..hi } else { lo..lo + 1.0 })
}

/// Log y range covering the drawable points of all curves (a default range if none).
fn log_range(curves: &[Curve]) -> Range<f64> {
    let (lo, hi) = curves
        .iter()
        .flat_map(|c| c.segments().into_iter().flatten())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), (_, y)| {
            (a.min(y), b.max(y))
        });
    if !(lo.is_finite() && hi.is_finite()) {
        return 0.1..10.0;
    }
    let (lo, hi) = if hi > lo {
        (lo, hi)
    } else {
        (lo / 2.0, hi * 2.0)
    };
    (lo / 1.25)..(hi * 1.25)
}

/// A "nice" step (1, 2 or 5 times a power of ten) near `raw` (> 0).
fn nice_step(raw: f64) -> f64 {
    let p = 10f64.powf(raw.log10().floor());
    let m = raw / p;
    let n = if m <= 1.0 {
        1.0
    } else if m <= 2.0 {
        2.0
    } else if m <= 5.0 {
        5.0
    } else {
        10.0
    };
    n * p
}

/// Labelled (bold) and unlabelled (light) tick values of a log axis over `range`
/// (finite, `0 < start < end`): powers of ten over many decades, 1-2-5 over a few, nice
/// linear steps within less than a decade.
pub(super) fn log_ticks(range: &Range<f64>) -> (Vec<f64>, Vec<f64>) {
    let (lo, hi) = (range.start, range.end);
    let inside = |v: &f64| *v >= lo * (1.0 - 1e-12) && *v <= hi * (1.0 + 1e-12);
    let decades = (hi / lo).log10();
    let (mut bold, mut light) = (Vec::new(), Vec::new());
    if !(decades.is_finite() && decades > 0.0) {
        return (bold, light);
    }
    if decades <= 1.0 {
        let step = nice_step((hi - lo) / 5.0);
        let first = (lo / step).ceil() as i64;
        let last = (hi / step).floor() as i64;
        bold.extend((first..=last).map(|i| i as f64 * step).filter(|v| *v > 0.0));
        let fine = step / 5.0;
        let first = (lo / fine).ceil() as i64;
        let last = (hi / fine).floor() as i64;
        light.extend((first..=last).map(|i| i as f64 * fine).filter(|v| *v > 0.0));
        return (bold, light);
    }
    let e_lo = lo.log10().floor() as i32;
    let e_hi = hi.log10().ceil() as i32;
    let every = (decades / 8.0).ceil().max(1.0) as i32;
    for e in e_lo..=e_hi {
        let p = 10f64.powi(e);
        for m in 1..10 {
            let v = f64::from(m) * p;
            if !inside(&v) {
                continue;
            }
            let is_bold = if decades > 2.5 {
                m == 1 && e.rem_euclid(every) == 0
            } else {
                matches!(m, 1 | 2 | 5)
            };
            if is_bold {
                bold.push(v);
            } else if decades <= 8.0 || m == 1 {
                light.push(v);
            }
        }
    }
    (bold, light)
}

/// A tick label: three significant digits without trailing zeros.
pub(super) fn fmt_tick(v: f64) -> String {
    fmt_trim(v, 3)
}

fn draw_err(what: &str, e: impl std::fmt::Display) -> String {
    format!("cannot draw {what}: {e}")
}

/// Draws `curves` into `area` with a linear time axis and a log y-axis.
fn draw_log_panel(
    area: &DrawingArea<BitMapBackend<'_>, Shift>,
    what: &str,
    caption: Option<&str>,
    y_desc: &str,
    x_range: Range<f64>,
    curves: &[Curve],
    legend: bool,
) -> Result<(), String> {
    let y_range = log_range(curves);
    let mut builder = ChartBuilder::on(area);
    builder
        .margin(10)
        .x_label_area_size(45)
        .y_label_area_size(80);
    if let Some(c) = caption {
        builder.caption(c, ("sans-serif", 24));
    }
    let (bold, light) = log_ticks(&y_range);
    let y_axis = y_range
        .log_scale()
        .with_key_points(bold)
        .with_light_points(light);
    let mut chart = builder
        .build_cartesian_2d(x_range, y_axis)
        .map_err(|e| draw_err(what, e))?;
    chart
        .configure_mesh()
        .x_desc("time [s]")
        .y_desc(y_desc)
        .y_label_formatter(&|v| fmt_tick(*v))
        .x_label_formatter(&|v| fmt_tick(*v))
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 16))
        .draw()
        .map_err(|e| draw_err(what, e))?;
    for c in curves {
        let style = c.color.stroke_width(2);
        // Unlabelled curves (the upper band line) get no legend entry.
        let mut labelled = c.label.is_empty();
        for seg in c.segments() {
            let anno = if c.dashed {
                chart.draw_series(DashedLineSeries::new(seg, 8, 5, style))
            } else {
                chart.draw_series(LineSeries::new(seg, style))
            }
            .map_err(|e| draw_err(what, e))?;
            if !labelled {
                let color = c.color;
                anno.label(c.label.as_str()).legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                });
                labelled = true;
            }
        }
    }
    if legend {
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 14))
            .draw()
            .map_err(|e| draw_err(what, e))?;
    }
    Ok(())
}

/// One single-panel PNG of `curves`.
fn single_plot(
    path: &Path,
    title: &str,
    y_desc: &str,
    x_range: Range<f64>,
    curves: &[Curve],
) -> Result<(), String> {
    let what = path.display().to_string();
    let root = BitMapBackend::new(path, PLOT_SIZE).into_drawing_area();
    root.fill(&WHITE).map_err(|e| draw_err(&what, e))?;
    draw_log_panel(&root, &what, Some(title), y_desc, x_range, curves, true)?;
    root.present().map_err(|e| draw_err(&what, e))
}

/// The filters' RMSE curves (`pick` chooses the series) and the PCRLB's root, dashed.
fn rmse_curves(r: &McResult, pick: impl Fn(&[[f64; 6]]) -> Vec<f64>) -> Vec<Curve> {
    let mut curves: Vec<Curve> = r
        .filters
        .iter()
        .enumerate()
        .map(|(i, f)| Curve::new(&f.label, color_of(i), false, &r.t, &pick(&f.mse)))
        .collect();
    if let Ok(j) = &r.pcrlb {
        curves.push(Curve::new("PCRLB", BLACK, true, &r.t, &pick(j)));
    }
    curves
}

/// The three-panel plot of the x, y and z RMSE (with the PCRLB) into `path`.
fn axes_plot(r: &McResult, path: &Path, x_range: Range<f64>) -> Result<(), String> {
    let what = path.display().to_string();
    let root = BitMapBackend::new(path, AXES_PLOT_SIZE).into_drawing_area();
    root.fill(&WHITE).map_err(|e| draw_err(&what, e))?;
    let body = root
        .titled(&r.title, ("sans-serif", 24))
        .map_err(|e| draw_err(&what, e))?;
    let panels = body.split_evenly((3, 1));
    for (axis, (panel, name)) in panels.iter().zip(["x", "y", "z"]).enumerate() {
        let pick = |v: &[[f64; 6]]| -> Vec<f64> {
            rmse_axes(v)
                .iter()
                .map(|a| a.get(axis).copied().unwrap_or(f64::NAN))
                .collect()
        };
        let curves = rmse_curves(r, pick);
        let y_desc = format!("{name} RMSE [m]");
        draw_log_panel(
            panel,
            &what,
            None,
            &y_desc,
            x_range.clone(),
            &curves,
            axis == 0,
        )?;
    }
    root.present().map_err(|e| draw_err(&what, e))
}

/// Writes the PNG plots into `dir` (created if needed) and returns their paths:
///
/// - `position_rmse.png`, `velocity_rmse.png`: RMSE versus time, one line per filter,
///   the PCRLB's root as a dashed black line "PCRLB" (when defined), log y-axis;
/// - `nees.png`: mean NEES versus time with the per-time 95 % band
///   `chi2inv(0.025, 6M)/M .. chi2inv(0.975, 6M)/M` as two dashed lines (one band per
///   distinct number `M` of runs used by the filters), log y-axis;
/// - `position_error_axes.png`: three stacked panels, x, y and z RMSE with the PCRLB;
/// - `range.png`: the RMS range error of each filter (solid), the root of the mean range
///   variance it reports (its `range_sigma`, dashed, same colour) and the run-wise bound of
///   the range (each run's bound along its own line of sight; black, dashed).
///
/// The title is the scenario title. Non-finite and non-positive values are left out
/// (lines break there). Errors (missing font [`FONT_PATH`], unwritable directory, no
/// finite times) are returned, never panicked.
pub fn write_plots(r: &McResult, dir: &Path) -> Result<Vec<PathBuf>, String> {
    ensure_font()?;
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let x_range = time_range(&r.t)?;
    let mut paths = Vec::new();

    let p = dir.join("position_rmse.png");
    let curves = rmse_curves(r, rmse_pos);
    single_plot(&p, &r.title, "position RMSE [m]", x_range.clone(), &curves)?;
    paths.push(p);

    let p = dir.join("velocity_rmse.png");
    let curves = rmse_curves(r, rmse_vel);
    single_plot(
        &p,
        &r.title,
        "velocity RMSE [m/s]",
        x_range.clone(),
        &curves,
    )?;
    paths.push(p);

    let p = dir.join("nees.png");
    let mut curves: Vec<Curve> = r
        .filters
        .iter()
        .enumerate()
        .map(|(i, f)| Curve::new(&f.label, color_of(i), false, &r.t, &f.nees))
        .collect();
    let counts: BTreeSet<u32> = r
        .filters
        .iter()
        .map(|f| r.runs.saturating_sub(f.failed_runs))
        .filter(|m| *m > 0)
        .collect();
    let ends = [x_range.start, x_range.end];
    for (i, m) in counts.iter().rev().enumerate() {
        let (lo, hi) = chi2_mean_bounds(6, u64::from(*m));
        let color = if i == 0 {
            BLACK
        } else {
            RGBColor(128, 128, 128)
        };
        curves.push(Curve::new(
            &format!("95 % band (M = {m})"),
            color,
            true,
            &ends,
            &[lo, lo],
        ));
        curves.push(Curve::new("", color, true, &ends, &[hi, hi]));
    }
    single_plot(&p, &r.title, "mean NEES [-]", x_range.clone(), &curves)?;
    paths.push(p);

    let p = dir.join("position_error_axes.png");
    axes_plot(r, &p, x_range.clone())?;
    paths.push(p);

    let p = dir.join("range.png");
    let mut curves = Vec::new();
    for (i, f) in r.filters.iter().enumerate() {
        let rmse: Vec<f64> = f.range_mse.iter().map(|v| v.sqrt()).collect();
        let sigma: Vec<f64> = f.range_var.iter().map(|v| v.sqrt()).collect();
        curves.push(Curve::new(&f.label, color_of(i), false, &r.t, &rmse));
        curves.push(Curve::new(
            &format!("{} range_sigma", f.label),
            color_of(i),
            true,
            &r.t,
            &sigma,
        ));
    }
    if !r.range_bound_runs.is_empty() {
        let b: Vec<f64> = r.range_bound_runs.iter().map(|v| v.sqrt()).collect();
        curves.push(Curve::new("run-wise bound", BLACK, true, &r.t, &b));
    }
    single_plot(
        &p,
        &r.title,
        "range RMSE, reported range_sigma [m]",
        x_range,
        &curves,
    )?;
    paths.push(p);

    Ok(paths)
}
