//! Error against run time: every integrator on five reference problems, swept over the time
//! step, timed (median of 5 runs after a warm-up), written as a CSV, a Markdown table and a
//! work-precision plot per problem (log error against log wall time).
//!
//! ```sh
//! cargo run --example accuracy_report --no-default-features --features report -- [DIR]
//! ```
//!
//! `DIR` defaults to `target/report/`. Written there: `accuracy.csv`, `accuracy.md`,
//! `work_precision_<problem>.png` for each problem and `work_precision.png` with all of them.
//! Runs that blew up are drawn as crosses along the top edge of their plot, not dropped.

use bevy_burning_cloth::report::accuracy::{self, Problem, Sample, Sweep};
use bevy_burning_cloth::sim::Integrator;
use plotters::prelude::*;
use std::error::Error;
use std::path::{Path, PathBuf};

/// The font the plots are labelled with (Fira Mono, SIL Open Font License; see
/// `assets/fonts/README.md`).
const FONT: &[u8] = include_bytes!("../assets/fonts/FiraMono-subset.ttf");

fn main() -> Result<(), Box<dyn Error>> {
    let dir = std::env::args()
        .nth(1)
        .map_or_else(|| PathBuf::from("target/report"), PathBuf::from);
    plotters::style::register_font("sans-serif", FontStyle::Normal, FONT)
        .map_err(|_| "the bundled font is not a valid OpenType font")?;

    let sweep = Sweep::full();
    eprintln!(
        "sweeping {} integrators x {} steps on a {} x {} cloth, {} repeats each ...",
        sweep.integrators.len(),
        sweep.steps.len(),
        sweep.cloth_size,
        sweep.cloth_size,
        sweep.repeats
    );
    let samples = accuracy::run(&sweep);
    let stable: Vec<(Integrator, Option<f32>)> = sweep
        .integrators
        .iter()
        .map(|&integrator| {
            (
                integrator,
                accuracy::largest_stable_step(sweep.cloth_size, integrator),
            )
        })
        .collect();
    let [csv, md] = accuracy::write_tables(&dir, &samples, &stable)?;
    println!("{}", std::fs::read_to_string(&md)?);

    let mut written = vec![csv, md];
    for problem in Problem::ALL {
        let path = dir.join(format!("work_precision_{}.png", problem.name()));
        save_png(&path, (1000, 640), |area| {
            let (chart, legend_area) = area.split_horizontally(760);
            plot(&chart, problem, &samples)?;
            legend(&legend_area, &methods_of(&samples, Some(problem)))
        })?;
        written.push(path);
    }
    let path = dir.join("work_precision.png");
    save_png(&path, (1500, 1000), |area| {
        let panels = area.split_evenly((2, 3));
        for (panel, problem) in panels.iter().zip(Problem::ALL) {
            plot(panel, problem, &samples)?;
        }
        legend(&panels[5], &methods_of(&samples, None))
    })?;
    written.push(path);
    for path in written {
        eprintln!("wrote {}", path.display());
    }
    Ok(())
}

type Area<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;

/// Draws into an RGB buffer and saves it as a PNG.
fn save_png(
    path: &Path,
    (width, height): (u32, u32),
    draw: impl FnOnce(&Area) -> Result<(), Box<dyn Error>>,
) -> Result<(), Box<dyn Error>> {
    let mut buffer = vec![0u8; (width * height * 3) as usize];
    {
        let area = BitMapBackend::with_buffer(&mut buffer, (width, height)).into_drawing_area();
        area.fill(&WHITE)?;
        draw(&area)?;
        area.present()?;
    }
    image::save_buffer(path, &buffer, width, height, image::ExtendedColorType::Rgb8)?;
    Ok(())
}

/// One colour per method, stable across plots.
fn colour(method: &str) -> RGBColor {
    let palette = [
        RGBColor(0x1f, 0x77, 0xb4),
        RGBColor(0xd6, 0x27, 0x28),
        RGBColor(0x2c, 0xa0, 0x2c),
        RGBColor(0x94, 0x67, 0xbd),
        RGBColor(0xff, 0x7f, 0x0e),
        RGBColor(0x8c, 0x56, 0x4b),
    ];
    let index = Integrator::ALL
        .iter()
        .position(|i| i.name() == method)
        .unwrap_or(palette.len() - 1);
    palette[index]
}

/// The methods of `problem`'s samples (or of all), in first-seen order.
fn methods_of(samples: &[Sample], problem: Option<Problem>) -> Vec<&'static str> {
    let mut methods: Vec<&'static str> = Vec::new();
    for s in samples {
        if problem.is_none_or(|p| p == s.problem) && !methods.contains(&s.method) {
            methods.push(s.method);
        }
    }
    methods
}

/// The key: a line per method, and what the crosses and axes mean.
fn legend(area: &Area, methods: &[&str]) -> Result<(), Box<dyn Error>> {
    let text = ("sans-serif", 17).into_font();
    let mut y = 60;
    for method in methods {
        let colour = colour(method);
        area.draw(&PathElement::new(
            vec![(20, y), (60, y)],
            colour.stroke_width(3),
        ))?;
        area.draw(&Circle::new((40, y), 4, colour.filled()))?;
        area.draw(&Text::new(method.to_string(), (72, y - 9), text.clone()))?;
        y += 30;
    }
    y += 10;
    area.draw(&Cross::new((40, y), 6, BLACK.stroke_width(2)))?;
    area.draw(&Text::new("blew up", (72, y - 9), text.clone()))?;
    let small = ("sans-serif", 14).into_font();
    for (i, line) in [
        "Each curve runs through the time",
        "steps 1/30 s (left) to 1/3840 s;",
        "cost is the median wall time per",
        "simulated second; crosses along",
        "the top are runs that blew up.",
        "Heat: grid spacings 40 mm to",
        "2.5 mm, steps dx^2/(8 alpha).",
    ]
    .iter()
    .enumerate()
    {
        area.draw(&Text::new(
            line.to_string(),
            (20, y + 30 + 20 * i as i32),
            small.clone(),
        ))?;
    }
    Ok(())
}

/// The work-precision plot of one problem: log error against log wall time per simulated
/// second, one curve per method through its time steps; blow-ups as crosses on the top edge.
fn plot(area: &Area, problem: Problem, samples: &[Sample]) -> Result<(), Box<dyn Error>> {
    let rows: Vec<&Sample> = samples.iter().filter(|s| s.problem == problem).collect();
    let finite = rows.iter().filter(|s| !s.blew_up && s.error > 0.0);
    let (mut error_min, mut error_max) = (f64::INFINITY, 0.0f64);
    for s in finite {
        error_min = error_min.min(s.error);
        error_max = error_max.max(s.error);
    }
    if !error_max.is_finite() || error_max <= 0.0 {
        (error_min, error_max) = (1e-6, 1.0);
    }
    let (error_low, error_high) = (decade_below(error_min), decade_above(error_max) * 10.0);
    let cost_ms = |s: &Sample| s.cost * 1e3;
    let cost_min = rows
        .iter()
        .map(|s| cost_ms(s))
        .fold(f64::INFINITY, f64::min);
    let cost_max = rows.iter().map(|s| cost_ms(s)).fold(0.0, f64::max);
    let (cost_low, cost_high) = (decade_below(cost_min), decade_above(cost_max));

    let mut chart = ChartBuilder::on(area)
        .caption(problem.name().replace('_', " "), ("sans-serif", 22))
        .margin(12)
        .x_label_area_size(44)
        .y_label_area_size(70)
        .build_cartesian_2d(
            (cost_low..cost_high).log_scale(),
            (error_low..error_high).log_scale(),
        )?;
    chart
        .configure_mesh()
        .x_desc("wall ms per simulated second")
        .y_desc(problem.error_label())
        .x_label_formatter(&|x| format!("{x:.0e}"))
        .y_label_formatter(&|y| format!("{y:.0e}"))
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 15))
        .draw()?;

    for method in methods_of(samples, Some(problem)) {
        let colour = colour(method);
        let mut points: Vec<&&Sample> = rows.iter().filter(|s| s.method == method).collect();
        // Along the sweep, largest step first: timing noise may make a curve turn back.
        points.sort_by(|a, b| b.parameter.total_cmp(&a.parameter));
        let curve: Vec<(f64, f64)> = points
            .iter()
            .filter(|s| !s.blew_up && s.error > 0.0)
            .map(|s| (cost_ms(s), s.error))
            .collect();
        chart.draw_series(LineSeries::new(
            curve.iter().copied(),
            colour.stroke_width(2),
        ))?;
        chart.draw_series(
            curve
                .iter()
                .map(|&point| Circle::new(point, 4, colour.filled())),
        )?;
        let blown_up_at = error_high / 2.0;
        chart.draw_series(
            points
                .iter()
                .filter(|s| s.blew_up)
                .map(|s| Cross::new((cost_ms(s), blown_up_at), 6, colour.stroke_width(2))),
        )?;
    }
    Ok(())
}

fn decade_below(x: f64) -> f64 {
    10f64.powf(x.max(1e-12).log10().floor())
}

fn decade_above(x: f64) -> f64 {
    10f64.powf(x.max(1e-12).log10().ceil())
}
