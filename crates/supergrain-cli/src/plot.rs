//! The measures' plots: each `run --measures DIR` CSV drawn as a PNG line chart beside it
//! (issue 41), with the plotters crate. The text is set in Ubuntu Light from egui's default
//! fonts (built for the viewer already), registered once, so nothing depends on the machine's
//! fonts.

use std::path::Path;
use std::sync::Once;

use anyhow::{Context, Result};
use plotters::prelude::*;
use supergrain::measure::series::SeriesKind;

use crate::output::Output;

const SIZE: (u32, u32) = (800, 480);

/// The lines to draw: a label and its `(time, value)` points.
type Lines = Vec<(String, Vec<(f64, f64)>)>;

/// The columns a kind plots against time, and the axes' labels; a profile's last slices as
/// `vx` against height.
fn lines_of(kind: SeriesKind, csv: &str) -> Result<(Lines, &'static str, &'static str)> {
    let mut reader = csv::Reader::from_reader(csv.as_bytes());
    let header = reader.headers()?.clone();
    let column = |name: &str| {
        header
            .iter()
            .position(|h| h == name)
            .with_context(|| format!("no column {name} in the {} CSV", kind.name()))
    };
    let time = column("time")?;
    let number = |r: &csv::StringRecord, k: usize| r.get(k).and_then(|v| v.parse::<f64>().ok());
    let rows: Vec<csv::StringRecord> = reader.records().collect::<Result<_, _>>()?;
    let mut lines: Lines = Vec::new();
    if kind == SeriesKind::Profile {
        let (step, y, vx, n) = (
            column("step")?,
            column("y")?,
            column("vx")?,
            column("grains")?,
        );
        let last = rows
            .iter()
            .filter_map(|r| number(r, step))
            .fold(f64::NAN, f64::max);
        // The slices that hold grains (an empty one has no velocity).
        let points = rows
            .iter()
            .filter(|r| number(r, step) == Some(last) && number(r, n).is_some_and(|n| n > 0.0))
            .filter_map(|r| Some((number(r, vx)?, number(r, y)?)))
            .collect();
        lines.push(("vx".to_string(), points));
        return Ok((lines, "mean horizontal velocity, last row", "height"));
    }
    let (columns, label): (&[&str], &'static str) = match kind {
        SeriesKind::Discharge => (&["grains"], "grains taken"),
        SeriesKind::Energy => (&["total", "translational", "rotational"], "kinetic energy"),
        SeriesKind::Surface => (&["degrees"], "free surface (degrees)"),
        SeriesKind::Packing => (&["area_fraction", "contact_number"], "packing"),
        SeriesKind::Profile => unreachable!("drawn above"),
    };
    // A discharge has a row per sink: a line each.
    let sink = (kind == SeriesKind::Discharge)
        .then(|| column("sink"))
        .transpose()?;
    for name in columns {
        let k = column(name)?;
        for r in &rows {
            let (Some(t), Some(v)) = (number(r, time), number(r, k)) else {
                continue;
            };
            let which = match sink {
                Some(s) => format!("sink {}", r.get(s).unwrap_or("?")),
                None => (*name).to_string(),
            };
            match lines.iter_mut().find(|l| l.0 == which) {
                Some(l) => l.1.push((t, v)),
                None => lines.push((which, vec![(t, v)])),
            }
        }
    }
    Ok((lines, "time", label))
}

/// Draws the CSV `csv` of a measure of `kind` into `out` as a PNG.
pub fn plot(kind: SeriesKind, csv: &Path, mut out: Output) -> Result<()> {
    static FONT: Once = Once::new();
    FONT.call_once(|| {
        // A font that cannot be read leaves the chart without text, not without a chart.
        let _ = plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            epaint_default_fonts::UBUNTU_LIGHT,
        );
    });
    let text =
        std::fs::read_to_string(csv).with_context(|| format!("cannot read {}", csv.display()))?;
    let (lines, x_label, label) = lines_of(kind, &text)?;
    let points = lines.iter().flat_map(|l| l.1.iter());
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for &(x, y) in points {
        if x.is_finite() && y.is_finite() {
            (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
        }
    }
    // No row with a number (a surface too small to fit, a region left empty): an empty chart,
    // not a failed run.
    if !(x0.is_finite() && y0.is_finite()) {
        (x0, x1, y0, y1) = (0.0, 1.0, 0.0, 1.0);
    }
    if x1 <= x0 {
        x1 = x0 + 1.0;
    }
    let pad = 0.05 * (y1 - y0).abs().max(1e-12 * y1.abs().max(1.0));
    let (y0, y1) = (y0 - pad, y1 + pad);
    let mut buffer = vec![0u8; (SIZE.0 * SIZE.1 * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buffer, SIZE).into_drawing_area();
        let draw = |e| anyhow::anyhow!("cannot draw the plot: {e:?}");
        root.fill(&WHITE).map_err(draw)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(kind.name(), ("sans-serif", 22))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(draw)?;
        chart
            .configure_mesh()
            .x_desc(x_label)
            .y_desc(label)
            .draw()
            .map_err(draw)?;
        let colours = [
            RGBColor(0x1e, 0x88, 0xe5),
            RGBColor(0xe5, 0x39, 0x35),
            RGBColor(0x43, 0xa0, 0x47),
            RGBColor(0x8e, 0x24, 0xaa),
        ];
        for (k, (name, points)) in lines.iter().enumerate() {
            let colour = colours[k % colours.len()];
            chart
                .draw_series(LineSeries::new(
                    points.iter().copied(),
                    colour.stroke_width(2),
                ))
                .map_err(draw)?
                .label(name.clone())
                .legend(move |(x, y)| {
                    PathElement::new([(x, y), (x + 20, y)], colour.stroke_width(2))
                });
        }
        if lines.len() > 1 {
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.8))
                .border_style(BLACK)
                .draw()
                .map_err(draw)?;
        }
        root.present().map_err(draw)?;
    }
    let image = image::RgbImage::from_raw(SIZE.0, SIZE.1, buffer).context("the plot's pixels")?;
    image::codecs::png::PngEncoder::new(&mut out)
        .write_image(
            image.as_raw(),
            SIZE.0,
            SIZE.1,
            image::ExtendedColorType::Rgb8,
        )
        .context("cannot encode the plot")?;
    out.finish()
}

use image::ImageEncoder;
