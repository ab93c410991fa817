//! The chart `docs/trade.svg`: cost against error per setting, one log-log panel
//! per scene, the Pareto front as a labelled staircase.

use super::entries::{Entry, of_scene, short, short_base};
use super::{EXACT, FAST, REFERENCE, SIZE};
use crate::thousands_rounded as thousands;
use plotters::coord::Shift;
use plotters::coord::combinators::{LogCoord, WithKeyPoints};
use plotters::prelude::*;
use tessera::builtin::Builtin;

const EXACT_COLOUR: RGBColor = RGBColor(31, 100, 200);
const FAST_COLOUR: RGBColor = RGBColor(230, 120, 0);
const REFERENCE_COLOUR: RGBColor = RGBColor(140, 140, 140);

/// A panel's drawing area and its log-log chart.
type Area<'b> = DrawingArea<SVGBackend<'b>, Shift>;
type Axis = WithKeyPoints<LogCoord<f64>>;
type Chart<'a, 'b> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<Axis, Axis>>;

/// A plotting failure as the report's error.
fn err(e: &dyn std::fmt::Debug) -> String {
    format!("drawing the chart: {e:?}")
}

/// The whole chart, as SVG text.
pub(super) fn svg(entries: &[Entry]) -> Result<String, String> {
    let mut svg = String::new();
    {
        let area = SVGBackend::with_string(&mut svg, (1280, 980)).into_drawing_area();
        area.fill(&WHITE).map_err(|e| err(&e))?;
        let area = area
            .titled(
                &format!(
                    "Cost against error, per setting ({SIZE}, host, one thread; lower left is better)"
                ),
                ("sans-serif", 22),
            )
            .map_err(|e| err(&e))?;
        for (area, b) in area.split_evenly((2, 2)).iter().zip(Builtin::ALL) {
            panel(area, b, &of_scene(entries, b.name()))?;
        }
        area.present().map_err(|e| err(&e))?;
    }
    Ok(svg)
}

/// One scene's panel: the axes, the points of the three backends, the front.
fn panel(area: &Area<'_>, b: Builtin, rows: &[&Entry]) -> Result<(), String> {
    let mut c = axes(area, b, rows)?;
    let best = front_by_cost(rows);
    points(&mut c, rows, &best)?;
    front(&mut c, &best)?;
    c.configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.4))
        .label_font(("sans-serif", 12))
        .draw()
        .map_err(|e| err(&e))
}

/// The panel's log-log axes, ranging a little beyond its rows, with 1-2-5 ticks.
fn axes<'a, 'b>(area: &'a Area<'b>, b: Builtin, rows: &[&Entry]) -> Result<Chart<'a, 'b>, String> {
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, 0.0f64, f64::MAX, 0.0f64);
    for e in rows {
        x0 = x0.min(e.row.ns_median);
        x1 = x1.max(e.row.ns_median);
        y0 = y0.min(e.row.flip);
        y1 = y1.max(e.row.flip);
    }
    let (x0, x1) = (x0 / 1.3, x1 * 1.6);
    let (y0, y1) = (y0 / 1.4, y1 * 1.6);
    let (xk, yk) = (ticks(x0, x1), ticks(y0, y1));
    let mut c = ChartBuilder::on(area)
        .caption(
            format!("{} (scene settings: {})", b.name(), short_base(b)),
            ("sans-serif", 17),
        )
        .margin(12)
        .x_label_area_size(42)
        .y_label_area_size(62)
        .build_cartesian_2d(
            (x0..x1).log_scale().with_key_points(xk),
            (y0..y1).log_scale().with_key_points(yk),
        )
        .map_err(|e| err(&e))?;
    c.configure_mesh()
        .x_desc("host ns per pixel (median, log scale)")
        .y_desc("mean FLIP vs converged (log scale)")
        .x_label_formatter(&|v| thousands(*v))
        .y_label_formatter(&|v| {
            format!("{v:.4}")
                .trim_end_matches('0')
                .trim_end_matches('.')
                .to_string()
        })
        .light_line_style(WHITE.mix(0.0))
        .label_style(("sans-serif", 12))
        .axis_desc_style(("sans-serif", 13))
        .draw()
        .map_err(|e| err(&e))?;
    Ok(c)
}

/// The front as a staircase (what the best setting up to a cost achieves), then the
/// rows of each backend: grey crosses, blue dots, orange triangles.
fn points(c: &mut Chart<'_, '_>, rows: &[&Entry], front: &[&Entry]) -> Result<(), String> {
    let pts = |backend: &str| -> Vec<(f64, f64)> {
        rows.iter()
            .filter(|e| e.row.backend == backend)
            .map(|e| (e.row.ns_median, e.row.flip))
            .collect()
    };
    let mut stair = Vec::new();
    for (i, e) in front.iter().enumerate() {
        if i > 0 {
            stair.push((e.row.ns_median, front[i - 1].row.flip));
        }
        stair.push((e.row.ns_median, e.row.flip));
    }
    c.draw_series(LineSeries::new(stair, BLACK.stroke_width(1)))
        .map_err(|e| err(&e))?
        .label("Pareto front (exact + fast-math)")
        .legend(|(x, y)| PathElement::new(vec![(x - 9, y), (x + 9, y)], BLACK));
    c.draw_series(
        pts(REFERENCE)
            .into_iter()
            .map(|p| Cross::new(p, 4, REFERENCE_COLOUR.stroke_width(2))),
    )
    .map_err(|e| err(&e))?
    .label("f64 reference (ceiling, 1 run)")
    .legend(|(x, y)| Cross::new((x, y), 4, REFERENCE_COLOUR.stroke_width(2)));
    c.draw_series(
        pts(EXACT)
            .into_iter()
            .map(|p| Circle::new(p, 4, EXACT_COLOUR.filled())),
    )
    .map_err(|e| err(&e))?
    .label("exact (f32)")
    .legend(|(x, y)| Circle::new((x, y), 4, EXACT_COLOUR.filled()));
    c.draw_series(
        pts(FAST)
            .into_iter()
            .map(|p| TriangleMarker::new(p, 5, FAST_COLOUR.filled())),
    )
    .map_err(|e| err(&e))?
    .label("fast-math (f32)")
    .legend(|(x, y)| TriangleMarker::new((x, y), 5, FAST_COLOUR.filled()));
    Ok(())
}

/// Rings every front point; labels it unless the previous one (the next cheaper)
/// has the same label.
fn front(c: &mut Chart<'_, '_>, front: &[&Entry]) -> Result<(), String> {
    let mut last = String::new();
    c.draw_series(front.iter().map(|e| {
        let label = short(&e.row.scene, &e.row.setting);
        let text = if label == last {
            String::new()
        } else {
            label.clone()
        };
        last = label;
        EmptyElement::at((e.row.ns_median, e.row.flip))
            + Circle::new((0, 0), 8, BLACK.stroke_width(1))
            + Text::new(text, (7, -16), ("sans-serif", 11))
    }))
    .map_err(|e| err(&e))?;
    Ok(())
}

/// The panel's front rows, cheapest first.
fn front_by_cost<'a>(rows: &[&'a Entry]) -> Vec<&'a Entry> {
    let mut front: Vec<&Entry> = rows.iter().copied().filter(|e| e.front).collect();
    front.sort_by(|a, b| a.row.ns_median.total_cmp(&b.row.ns_median));
    front
}

/// The 1-2-5 values in `lo..hi`, the tick marks of a log axis.
fn ticks(lo: f64, hi: f64) -> Vec<f64> {
    let mut out = Vec::new();
    let mut decade = 10f64.powf(lo.log10().floor());
    while decade <= hi {
        for m in [1.0, 2.0, 5.0] {
            let v = decade * m;
            if (lo..=hi).contains(&v) {
                out.push(v);
            }
        }
        decade *= 10.0;
    }
    out
}
