//! Drawing a drive's bird's-eye view into a PNG: axes with metre ticks, the ground truth's
//! trajectories (wide grey bands), the ego trajectory (black, an arrow at its last pose), each
//! track's trajectory and last box in a colour per track id with a marker per class, a legend
//! in the emptiest corner and a scale bar. Text uses a font embedded in the binary, so no
//! system font is needed.

use std::sync::OnceLock;

use nalgebra::Vector3;
use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::{FontStyle, register_font};

use super::ground_truth::GtTrajectory;
use super::run_dir::{WorldDrive, WorldTrack};

/// The font family name the plot's text asks for.
const FONT: &str = "sans-serif";
/// The ground truth's colour.
const GT_COLOUR: RGBColor = RGBColor(200, 200, 200);
/// The ground truth's band width, in track strokes: wide, so that the tracks on it show.
const GT_WIDTH: u32 = 5;
/// Margin around the data's extent, as a share of its larger side.
const PAD_SHARE: f64 = 0.05;
/// Smallest margin around the data's extent (metres).
const MIN_PAD_M: f64 = 5.0;
/// Tracks beyond this count get no id label (they would hide each other).
const MAX_ID_LABELS: usize = 120;

/// What one image shows.
pub struct Scene<'a> {
    /// The title above the plot.
    pub title: &'a str,
    /// The run's ego poses and tracks.
    pub drive: &'a WorldDrive,
    /// Ground-truth trajectories (may be empty).
    pub gt: &'a [GtTrajectory],
}

/// A rendered image.
pub struct Plot {
    /// The PNG file's bytes.
    pub png: Vec<u8>,
    /// Where world coordinates fell in it.
    pub view: View,
}

/// How world coordinates (metres) map to the image's pixels.
#[derive(Clone, Copy, Debug)]
pub struct View {
    /// The pixel of the world origin.
    origin: (f64, f64),
    /// Pixels per metre along x (positive) and y (negative: rows grow downwards).
    scale: (f64, f64),
}

impl View {
    /// The pixel (column, row) of world point `p`.
    pub fn pixel(&self, p: [f64; 2]) -> (i32, i32) {
        (
            (self.origin.0 + p[0] * self.scale.0).round() as i32,
            (self.origin.1 + p[1] * self.scale.1).round() as i32,
        )
    }

    /// Metres a pixel spans.
    pub fn metres_per_pixel(&self) -> f64 {
        1.0 / self.scale.0
    }
}

/// The marker that tells a track's class.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Marker {
    Square,
    Triangle,
    Circle,
    Diamond,
    Plus,
}

/// The classes `tracks.csv` names, with their marker, in legend order.
const CLASSES: [(&str, Marker); 5] = [
    ("car", Marker::Square),
    ("cyclist", Marker::Triangle),
    ("pedestrian", Marker::Circle),
    ("other_movable", Marker::Diamond),
    ("unknown", Marker::Plus),
];

impl Marker {
    /// The marker of a class name (unknown names get the unknown class's).
    fn of(class: &str) -> Self {
        CLASSES
            .iter()
            .find(|(name, _)| *name == class)
            .map_or(Self::Plus, |(_, m)| *m)
    }

    /// The marker's outline around pixel `c`, `r` pixels in radius.
    fn polygon(self, c: (i32, i32), r: i32) -> Vec<(i32, i32)> {
        let at = |dx: f64, dy: f64| {
            (
                c.0 + (dx * r as f64).round() as i32,
                c.1 + (dy * r as f64).round() as i32,
            )
        };
        match self {
            Self::Square => vec![at(-0.8, -0.8), at(0.8, -0.8), at(0.8, 0.8), at(-0.8, 0.8)],
            Self::Triangle => vec![at(0.0, -1.0), at(0.9, 0.7), at(-0.9, 0.7)],
            Self::Circle => (0..16)
                .map(|k| {
                    let a = k as f64 * std::f64::consts::TAU / 16.0;
                    at(a.cos(), a.sin())
                })
                .collect(),
            Self::Diamond => vec![at(0.0, -1.0), at(1.0, 0.0), at(0.0, 1.0), at(-1.0, 0.0)],
            Self::Plus => {
                let (a, b) = (0.3, 1.0);
                [
                    (-a, -b),
                    (a, -b),
                    (a, -a),
                    (b, -a),
                    (b, a),
                    (a, a),
                    (a, b),
                    (-a, b),
                    (-a, a),
                    (-b, a),
                    (-b, -a),
                    (-a, -a),
                ]
                .map(|(x, y)| at(x, y))
                .to_vec()
            }
        }
    }
}

/// The colour of track `id`: hues spread by the golden ratio, so that consecutive ids differ.
pub fn track_colour(id: u64) -> RGBColor {
    let hue = (id as f64 * 0.618_033_988_749_895).fract();
    let (r, g, b) = HSLColor(hue, 0.85, 0.42).to_backend_color().rgb;
    RGBColor(r, g, b)
}

/// Registers the embedded font once (plotters' `ab_glyph` backend loads no system font).
fn register_embedded_font() -> anyhow::Result<()> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| {
        register_font(FONT, FontStyle::Normal, epaint_default_fonts::HACK_REGULAR).is_ok()
    });
    anyhow::ensure!(ok, "the embedded font (Hack Regular) does not parse");
    Ok(())
}

/// Renders `scene` as a `size` × `size` PNG.
pub fn render(scene: &Scene, size: u32) -> anyhow::Result<Plot> {
    anyhow::ensure!(
        !scene.drive.ego.is_empty(),
        "the run holds no ego pose: nothing to plot"
    );
    register_embedded_font()?;
    let mut rgb = vec![0u8; size as usize * size as usize * 3];
    let view = draw(scene, &mut rgb, size)?;
    Ok(Plot {
        png: encode_png(&rgb, size)?,
        view,
    })
}

/// Encodes an RGB buffer as PNG.
fn encode_png(rgb: &[u8], size: u32) -> anyhow::Result<Vec<u8>> {
    let mut png = Vec::new();
    let mut encoder = png::Encoder::new(&mut png, size, size);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_compression(png::Compression::High);
    let mut writer = encoder.write_header()?;
    writer.write_image_data(rgb)?;
    writer.finish()?;
    Ok(png)
}

/// Font sizes and strokes, in pixels, for an image of a given size.
#[derive(Clone, Copy)]
struct Sizes {
    text: f64,
    small: f64,
    title: f64,
    marker: i32,
    stroke: u32,
}

impl Sizes {
    fn for_image(size: u32) -> Self {
        let unit = (f64::from(size) / 100.0).max(8.0);
        Self {
            text: unit,
            small: unit * 0.8,
            title: unit * 1.5,
            marker: (unit * 0.45).round().max(3.0) as i32,
            stroke: (unit / 8.0).round().max(1.0) as u32,
        }
    }
}

/// Draws the scene into `rgb` and tells where the world went.
fn draw(scene: &Scene, rgb: &mut [u8], size: u32) -> anyhow::Result<View> {
    let sizes = Sizes::for_image(size);
    let root = BitMapBackend::with_buffer(rgb, (size, size)).into_drawing_area();
    root.fill(&WHITE)?;
    let area = root.titled(scene.title, (FONT, sizes.title))?;
    // The plotting area's pixel size, to give both axes the same scale.
    let (width_px, height_px) = chart_builder(&area, sizes)
        .build_cartesian_2d(0.0..1.0, 0.0..1.0)?
        .plotting_area()
        .dim_in_pixel();
    let (x_range, y_range) = equal_scale_ranges(&extent(scene), width_px, height_px);
    let mut chart =
        chart_builder(&area, sizes).build_cartesian_2d(x_range.clone(), y_range.clone())?;
    chart
        .configure_mesh()
        .x_desc("x (m, world frame)")
        .y_desc("y (m, world frame)")
        .label_style((FONT, sizes.text))
        .axis_desc_style((FONT, sizes.text))
        .x_label_formatter(&|v| format!("{v:.0}"))
        .y_label_formatter(&|v| format!("{v:.0}"))
        .light_line_style(RGBColor(238, 238, 238))
        .bold_line_style(RGBColor(210, 210, 210))
        .draw()?;
    let view = {
        let (x0, y0) = (x_range.start, y_range.start);
        let (x1, y1) = (x_range.end, y_range.end);
        let p0 = chart.backend_coord(&(x0, y0));
        let p1 = chart.backend_coord(&(x1, y1));
        let scale = (
            f64::from(p1.0 - p0.0) / (x1 - x0),
            f64::from(p1.1 - p0.1) / (y1 - y0),
        );
        View {
            origin: (
                f64::from(p0.0) - x0 * scale.0,
                f64::from(p0.1) - y0 * scale.1,
            ),
            scale,
        }
    };

    let stroke = sizes.stroke;
    for gt in scene.gt {
        chart.draw_series(LineSeries::new(
            gt.positions.iter().map(|p| (p[0], p[1])),
            GT_COLOUR.stroke_width(GT_WIDTH * stroke),
        ))?;
    }
    let ego: Vec<(f64, f64)> = scene
        .drive
        .ego
        .iter()
        .map(|p| (p.translation.x, p.translation.y))
        .collect();
    chart.draw_series(LineSeries::new(ego, BLACK.stroke_width(2 * stroke)))?;
    for track in &scene.drive.tracks {
        draw_track(&mut chart, track, stroke)?;
    }

    draw_ego_arrow(&root, scene, &view, sizes)?;
    let label_ids = scene.drive.tracks.len() <= MAX_ID_LABELS;
    for track in &scene.drive.tracks {
        let Some(last) = track.boxes.last() else {
            continue;
        };
        let c = view.pixel(last.centre);
        let style = ShapeStyle::from(&BLACK).filled();
        root.draw(&Polygon::new(
            Marker::of(&track.class).polygon(c, sizes.marker),
            style,
        ))?;
        if label_ids {
            root.draw(&Text::new(
                track.id.to_string(),
                (
                    c.0 + sizes.marker + 2,
                    c.1 - 2 * sizes.marker - sizes.small as i32,
                ),
                (FONT, sizes.small)
                    .into_font()
                    .color(&track_colour(track.id)),
            ))?;
        }
    }
    let plot_px = chart.plotting_area().get_pixel_range();
    draw_scale_bar(&root, &view, &plot_px, sizes)?;
    draw_legend(&root, scene, &view, &plot_px, sizes)?;
    root.present()?;
    Ok(view)
}

/// The chart's margins and label areas on `area`.
fn chart_builder<'a, 'b>(
    area: &'a DrawingArea<BitMapBackend<'b>, Shift>,
    sizes: Sizes,
) -> ChartBuilder<'a, 'b, BitMapBackend<'b>> {
    let px = |share: f64| (sizes.text * share).round() as u32;
    let mut builder = ChartBuilder::on(area);
    builder
        .margin(px(1.2))
        .x_label_area_size(px(3.0))
        .y_label_area_size(px(4.5));
    builder
}

/// A track's trajectory and its last box, in its colour.
fn draw_track(
    chart: &mut ChartContext<BitMapBackend, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    track: &WorldTrack,
    stroke: u32,
) -> anyhow::Result<()> {
    let colour = track_colour(track.id);
    chart.draw_series(LineSeries::new(
        track.boxes.iter().map(|b| (b.centre[0], b.centre[1])),
        colour.stroke_width(stroke),
    ))?;
    if let Some(last) = track.boxes.last() {
        let corners = last.corners();
        let outline: Vec<(f64, f64)> = corners
            .iter()
            .chain(corners.first())
            .map(|c| (c[0], c[1]))
            .collect();
        chart.draw_series(std::iter::once(PathElement::new(
            outline,
            colour.stroke_width(stroke),
        )))?;
    }
    Ok(())
}

/// An arrow at the ego's last pose, pointing where the sensor faces.
fn draw_ego_arrow(
    root: &DrawingArea<BitMapBackend, Shift>,
    scene: &Scene,
    view: &View,
    sizes: Sizes,
) -> anyhow::Result<()> {
    let Some(pose) = scene.drive.ego.last() else {
        return Ok(());
    };
    let ahead = pose.rotation * Vector3::x();
    let heading = ahead.y.atan2(ahead.x);
    let tip = view.pixel([pose.translation.x, pose.translation.y]);
    let r = f64::from(3 * sizes.marker);
    // Rows grow downwards: the pixel heading is mirrored.
    let at = |angle: f64, length: f64| {
        (
            tip.0 - (length * (heading + angle).cos()).round() as i32,
            tip.1 + (length * (heading + angle).sin()).round() as i32,
        )
    };
    root.draw(&Polygon::new(
        vec![tip, at(0.4, r), at(-0.4, r)],
        BLACK.filled(),
    ))?;
    Ok(())
}

/// A scale bar of a round length in the lower right corner of the plotting area.
fn draw_scale_bar(
    root: &DrawingArea<BitMapBackend, Shift>,
    view: &View,
    plot_px: &(std::ops::Range<i32>, std::ops::Range<i32>),
    sizes: Sizes,
) -> anyhow::Result<()> {
    let width_m = f64::from(plot_px.0.end - plot_px.0.start) * view.metres_per_pixel();
    let metres = round_length(width_m / 6.0);
    let length_px = (metres / view.metres_per_pixel()).round() as i32;
    let inset = (sizes.text * 1.5) as i32;
    let right = plot_px.0.end - inset;
    let y = plot_px.1.end - inset;
    let thick = (sizes.stroke * 3) as i32;
    root.draw(&Rectangle::new(
        [(right - length_px, y - thick), (right, y)],
        BLACK.filled(),
    ))?;
    for x in [right - length_px, right] {
        root.draw(&Rectangle::new(
            [(x - sizes.stroke as i32, y - 3 * thick), (x, y)],
            BLACK.filled(),
        ))?;
    }
    let label = format!("{metres} m");
    let font = (FONT, sizes.text).into_font();
    let (text_w, text_h) = root.estimate_text_size(&label, &font.clone().into())?;
    root.draw(&Text::new(
        label,
        (
            right - length_px / 2 - text_w as i32 / 2,
            y - 3 * thick - text_h as i32 - 2,
        ),
        font,
    ))?;
    Ok(())
}

/// The largest of 1, 2, 5 × 10^k metres not above `metres` (at least 1 m).
fn round_length(metres: f64) -> f64 {
    let decade = 10f64.powf(metres.max(1.0).log10().floor());
    [5.0, 2.0, 1.0]
        .into_iter()
        .map(|m| m * decade)
        .find(|&m| m <= metres)
        .unwrap_or(decade)
}

/// One row of the legend: what its sample shows.
enum Sample {
    /// A line in a colour, so many track strokes wide.
    Line(RGBColor, u32),
    /// A class marker.
    Marker(Marker),
}

/// The legend, in the corner of the plotting area (the lower right one excepted: the scale bar
/// is there) that hides the fewest drawn points.
fn draw_legend(
    root: &DrawingArea<BitMapBackend, Shift>,
    scene: &Scene,
    view: &View,
    plot_px: &(std::ops::Range<i32>, std::ops::Range<i32>),
    sizes: Sizes,
) -> anyhow::Result<()> {
    let mut rows = vec![(
        "ego trajectory, arrow at its last pose".to_string(),
        Sample::Line(BLACK, 2),
    )];
    if !scene.gt.is_empty() {
        rows.push((
            "ground truth (objects' centres)".into(),
            Sample::Line(GT_COLOUR, GT_WIDTH),
        ));
    }
    let sample_colour = scene
        .drive
        .tracks
        .first()
        .map_or(track_colour(1), |t| track_colour(t.id));
    rows.push((
        "track (colour per id), box at its last frame".into(),
        Sample::Line(sample_colour, 1),
    ));
    for (class, marker) in CLASSES {
        if scene
            .drive
            .tracks
            .iter()
            .any(|t| Marker::of(&t.class) == marker)
        {
            rows.push((format!("class {class}"), Sample::Marker(marker)));
        }
    }
    let font = (FONT, sizes.text).into_font();
    let line_h = (sizes.text * 1.5) as i32;
    let sample_w = (sizes.text * 2.5) as i32;
    let pad = (sizes.text * 0.6) as i32;
    let mut text_w = 0;
    for (label, _) in &rows {
        text_w = text_w.max(root.estimate_text_size(label, &font.clone().into())?.0 as i32);
    }
    let (w, h) = (
        3 * pad + sample_w + text_w,
        2 * pad + line_h * rows.len() as i32,
    );
    let inset = (sizes.text * 0.8) as i32;
    let (left, right) = (plot_px.0.start + inset, plot_px.0.end - inset - w);
    let (top, bottom) = (plot_px.1.start + inset, plot_px.1.end - inset - h);
    let corners = [(left, top), (right, top), (left, bottom)];
    let points = drawn_points(scene, view);
    let hidden = |(x, y): (i32, i32)| {
        points
            .iter()
            .filter(|p| p.0 >= x && p.0 <= x + w && p.1 >= y && p.1 <= y + h)
            .count()
    };
    let (x, y) = corners
        .into_iter()
        .min_by_key(|&c| hidden(c))
        .unwrap_or((left, top));
    root.draw(&Rectangle::new(
        [(x, y), (x + w, y + h)],
        WHITE.mix(0.9).filled(),
    ))?;
    root.draw(&Rectangle::new([(x, y), (x + w, y + h)], BLACK))?;
    for (i, (label, sample)) in rows.into_iter().enumerate() {
        let mid = y + pad + line_h * i as i32 + line_h / 2;
        let (s0, s1) = (x + pad, x + pad + sample_w);
        match sample {
            Sample::Line(colour, width) => root.draw(&PathElement::new(
                vec![(s0, mid), (s1, mid)],
                colour.stroke_width(width * sizes.stroke),
            ))?,
            Sample::Marker(marker) => root.draw(&Polygon::new(
                marker.polygon(((s0 + s1) / 2, mid), sizes.marker),
                BLACK.filled(),
            ))?,
        }
        root.draw(&Text::new(
            label,
            (s1 + pad, mid - (sizes.text * 0.5) as i32),
            font.clone(),
        ))?;
    }
    Ok(())
}

/// The ego positions and the ground truth's, in the world frame (m).
fn ego_and_gt_positions(scene: &Scene<'_>) -> impl Iterator<Item = [f64; 2]> {
    let ego = scene
        .drive
        .ego
        .iter()
        .map(|p| [p.translation.x, p.translation.y]);
    let gt = scene.gt.iter().flat_map(|g| g.positions.iter().copied());
    ego.chain(gt)
}

/// The pixels of every drawn position: ego poses, track boxes, ground truth.
fn drawn_points(scene: &Scene, view: &View) -> Vec<(i32, i32)> {
    let tracks = scene
        .drive
        .tracks
        .iter()
        .flat_map(|t| t.boxes.iter().map(|b| b.centre));
    ego_and_gt_positions(scene)
        .chain(tracks)
        .map(|p| view.pixel(p))
        .collect()
}

/// The data's extent (min x, min y, max x, max y) with a margin around it.
fn extent(scene: &Scene) -> [f64; 4] {
    let corners = scene
        .drive
        .tracks
        .iter()
        .flat_map(|t| t.boxes.iter().flat_map(|b| b.corners()));
    let mut e = [
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    ];
    for p in ego_and_gt_positions(scene).chain(corners) {
        e = [
            e[0].min(p[0]),
            e[1].min(p[1]),
            e[2].max(p[0]),
            e[3].max(p[1]),
        ];
    }
    let pad = ((e[2] - e[0]).max(e[3] - e[1]) * PAD_SHARE).max(MIN_PAD_M);
    [e[0] - pad, e[1] - pad, e[2] + pad, e[3] + pad]
}

/// Ranges around `extent` with the same metres per pixel on both axes of a `width` × `height`
/// pixel plotting area.
fn equal_scale_ranges(
    extent: &[f64; 4],
    width: u32,
    height: u32,
) -> (std::ops::Range<f64>, std::ops::Range<f64>) {
    let (w, h) = (f64::from(width.max(1)), f64::from(height.max(1)));
    let per_px = ((extent[2] - extent[0]) / w).max((extent[3] - extent[1]) / h);
    let (cx, cy) = ((extent[0] + extent[2]) / 2.0, (extent[1] + extent[3]) / 2.0);
    (
        cx - per_px * w / 2.0..cx + per_px * w / 2.0,
        cy - per_px * h / 2.0..cy + per_px * h / 2.0,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scale_bars_have_round_lengths() {
        assert_eq!(round_length(7.3), 5.0);
        assert_eq!(round_length(19.0), 10.0);
        assert_eq!(round_length(23.0), 20.0);
        assert_eq!(round_length(0.2), 1.0);
    }

    #[test]
    fn both_axes_get_the_same_scale() {
        let (x, y) = equal_scale_ranges(&[0.0, 0.0, 100.0, 10.0], 200, 100);
        assert!(((x.end - x.start) / 200.0 - (y.end - y.start) / 100.0).abs() < 1e-12);
        assert!(x.start <= 0.0 && x.end >= 100.0 && y.start <= 0.0 && y.end >= 10.0);
    }

    #[test]
    fn markers_differ_by_class() {
        assert_eq!(Marker::of("cyclist"), Marker::Triangle);
        assert_eq!(Marker::of("bus"), Marker::Plus);
        assert_ne!(track_colour(1), track_colour(2));
    }
}
