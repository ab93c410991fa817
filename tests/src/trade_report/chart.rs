//! The charts `docs/trade.svg` (host time) and `docs/trade-chip.svg` (the chip's
//! estimated cycles): cost against error per setting, one log-log panel per scene,
//! the Pareto front as a labelled staircase.

use super::entries::{Entry, of_scene, short, short_base};
use super::{BACKENDS, CHIP_SIZE, REFERENCE, SIZE};
use crate::thousands_rounded as thousands;
use plotters::coord::Shift;
use plotters::coord::combinators::{LogCoord, WithKeyPoints};
use plotters::prelude::*;
use tessera_core::builtin::Builtin;

/// The colours of the backends, in the order of [`BACKENDS`] (repeated beyond).
const COLOURS: [RGBColor; 6] = [
    RGBColor(31, 100, 200),
    RGBColor(230, 120, 0),
    RGBColor(40, 160, 60),
    RGBColor(200, 40, 40),
    RGBColor(130, 70, 180),
    RGBColor(140, 90, 40),
];
const REFERENCE_COLOUR: RGBColor = RGBColor(140, 140, 140);

/// A backend's colour.
fn colour(i: usize) -> RGBColor {
    COLOURS[i % COLOURS.len()]
}

/// What a chart puts on its cost axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Cost {
    /// Host nanoseconds per pixel (median), every row, the f64 reference too.
    Host,
    /// The chip's estimated cycles per pixel, the rows measured on the chip.
    Chip,
}

impl Cost {
    /// The chart's file name.
    pub(super) fn file(self) -> &'static str {
        match self {
            Cost::Host => "trade.svg",
            Cost::Chip => "trade-chip.svg",
        }
    }
    /// The cost of a row, if it has one on this axis.
    fn of(self, e: &Entry) -> Option<f64> {
        match self {
            Cost::Host => Some(e.row.ns_median),
            Cost::Chip => e.cycles(),
        }
    }
    /// Whether a row is on this cost's front.
    fn on_front(self, e: &Entry) -> bool {
        match self {
            Cost::Host => e.front,
            Cost::Chip => e.chip_front,
        }
    }
    fn axis(self) -> &'static str {
        match self {
            Cost::Host => "host ns per pixel (median, log scale)",
            Cost::Chip => "chip cycles per pixel (Cortex-M4 estimate, log scale)",
        }
    }
    fn title(self) -> String {
        match self {
            Cost::Host => format!(
                "Cost against error, per setting ({SIZE}, host, one thread; lower left is better)"
            ),
            Cost::Chip => format!(
                "Cost against error, per setting (chip, {CHIP_SIZE}x{CHIP_SIZE}, estimated \
                 Cortex-M4 cycles; lower left is better)"
            ),
        }
    }
}

/// A panel's drawing area and its log-log chart.
type Area<'b> = DrawingArea<SVGBackend<'b>, Shift>;
type Axis = WithKeyPoints<LogCoord<f64>>;
type Chart<'a, 'b> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<Axis, Axis>>;

/// A plotting failure as the report's error.
fn err(e: &dyn std::fmt::Debug) -> String {
    format!("drawing the chart: {e:?}")
}

/// The whole chart with `cost` on the cost axis, as SVG text.
pub(super) fn svg(entries: &[Entry], cost: Cost) -> Result<String, String> {
    let mut svg = String::new();
    {
        let area = SVGBackend::with_string(&mut svg, (1280, 980)).into_drawing_area();
        area.fill(&WHITE).map_err(|e| err(&e))?;
        let area = area
            .titled(&cost.title(), ("sans-serif", 22))
            .map_err(|e| err(&e))?;
        for (area, b) in area.split_evenly((2, 2)).iter().zip(super::SCENES) {
            let rows: Vec<&Entry> = of_scene(entries, b.name())
                .into_iter()
                .filter(|e| cost.of(e).is_some())
                .collect();
            if !rows.is_empty() {
                panel(area, b, &rows, cost)?;
            }
        }
        area.present().map_err(|e| err(&e))?;
    }
    Ok(svg)
}

/// One scene's panel: the axes, the points of the backends, the front.
fn panel(area: &Area<'_>, b: Builtin, rows: &[&Entry], cost: Cost) -> Result<(), String> {
    let mut c = axes(area, b, rows, cost)?;
    let best = front_by_cost(rows, cost);
    points(&mut c, rows, &best, cost)?;
    front(&mut c, &best, cost)?;
    c.configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.4))
        .label_font(("sans-serif", 12))
        .draw()
        .map_err(|e| err(&e))
}

/// The panel's log-log axes, ranging a little beyond its rows, with 1-2-5 ticks.
fn axes<'a, 'b>(
    area: &'a Area<'b>,
    b: Builtin,
    rows: &[&Entry],
    cost: Cost,
) -> Result<Chart<'a, 'b>, String> {
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, 0.0f64, f64::MAX, 0.0f64);
    for e in rows {
        let x = cost.of(e).unwrap_or(f64::NAN);
        x0 = x0.min(x);
        x1 = x1.max(x);
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
        .x_desc(cost.axis())
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
/// rows of each backend: grey crosses the f64 reference (host only), dots the
/// first backend (exact), triangles the others, one colour each.
fn points(
    c: &mut Chart<'_, '_>,
    rows: &[&Entry],
    front: &[&Entry],
    cost: Cost,
) -> Result<(), String> {
    let pts = |backend: &str| -> Vec<(f64, f64)> {
        rows.iter()
            .filter(|e| e.row.backend == backend)
            .filter_map(|e| cost.of(e).map(|x| (x, e.row.flip)))
            .collect()
    };
    let mut stair = Vec::new();
    for (i, e) in front.iter().enumerate() {
        let x = cost.of(e).unwrap_or(f64::NAN);
        if i > 0 {
            stair.push((x, front[i - 1].row.flip));
        }
        stair.push((x, e.row.flip));
    }
    let names: Vec<&str> = BACKENDS.iter().map(|b| b.name).collect();
    c.draw_series(LineSeries::new(stair, BLACK.stroke_width(1)))
        .map_err(|e| err(&e))?
        .label(format!("Pareto front ({})", names.join(" + ")))
        .legend(|(x, y)| PathElement::new(vec![(x - 9, y), (x + 9, y)], BLACK));
    let reference = pts(REFERENCE);
    if !reference.is_empty() {
        c.draw_series(
            reference
                .into_iter()
                .map(|p| Cross::new(p, 4, REFERENCE_COLOUR.stroke_width(2))),
        )
        .map_err(|e| err(&e))?
        .label("f64 reference (ceiling, 1 run)")
        .legend(|(x, y)| Cross::new((x, y), 4, REFERENCE_COLOUR.stroke_width(2)));
    }
    for (i, name) in names.iter().enumerate() {
        let colour = colour(i);
        let label = format!("{name} (f32)");
        if i == 0 {
            c.draw_series(
                pts(name)
                    .into_iter()
                    .map(|p| Circle::new(p, 4, colour.filled())),
            )
            .map_err(|e| err(&e))?
            .label(label)
            .legend(move |(x, y)| Circle::new((x, y), 4, colour.filled()));
        } else {
            c.draw_series(
                pts(name)
                    .into_iter()
                    .map(|p| TriangleMarker::new(p, 5, colour.filled())),
            )
            .map_err(|e| err(&e))?
            .label(label)
            .legend(move |(x, y)| TriangleMarker::new((x, y), 5, colour.filled()));
        }
    }
    Ok(())
}

/// Rings every front point; labels it unless the previous one (the next cheaper)
/// has the same label.
fn front(c: &mut Chart<'_, '_>, front: &[&Entry], cost: Cost) -> Result<(), String> {
    let mut last = String::new();
    c.draw_series(front.iter().map(|e| {
        let label = short(&e.row.scene, &e.row.setting);
        let text = if label == last {
            String::new()
        } else {
            label.clone()
        };
        last = label;
        EmptyElement::at((cost.of(e).unwrap_or(f64::NAN), e.row.flip))
            + Circle::new((0, 0), 8, BLACK.stroke_width(1))
            + Text::new(text, (7, -16), ("sans-serif", 11))
    }))
    .map_err(|e| err(&e))?;
    Ok(())
}

/// The panel's front rows on `cost`, cheapest first.
fn front_by_cost<'a>(rows: &[&'a Entry], cost: Cost) -> Vec<&'a Entry> {
    let mut front: Vec<&Entry> = rows.iter().copied().filter(|e| cost.on_front(e)).collect();
    front.sort_by(|a, b| {
        cost.of(a)
            .unwrap_or(f64::NAN)
            .total_cmp(&cost.of(b).unwrap_or(f64::NAN))
    });
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
