//! Heat maps: per-tile figures (polygon-list entries, fragments shaded, bytes stored) and
//! per-pixel overdraw drawn in colour over the dimmed picture, as PNGs and as the overlays
//! the HTML report lays over the picture.
//!
//! Colours come from viridis (perceptually uniform and readable with the common colour-vision
//! deficiencies). A tile or pixel with nothing in it is left uncoloured, so the picture shows
//! through where no work happened. Tile figures are scaled from 0 to the map's maximum;
//! overdraw uses whole-number steps from 1 to a top count shared by every map of a report, so
//! maps of different devices compare colour for colour.

use std::path::{Path, PathBuf};

use tiler::{PassReport, TileStats};

use crate::{Report, Rgba8Image};

/// Brightness the picture keeps under a map: dark enough for colours to dominate, light
/// enough to recognise the scene (chosen by eye on the built-in scene).
pub const DIM: f32 = 0.35;

/// Opacity of a map's colours over the dimmed picture (chosen by eye, as [`DIM`]).
pub const MAP_OPACITY: f32 = 0.8;

/// Overdraw scales run from 1 to at least this count, so a frame with little overdraw still
/// uses a spread of colours.
pub const OVERDRAW_TOP_MIN: u16 = 4;

/// And to at most this one: higher counts share the last colour. Eight steps keep 1, 2 and 3
/// — most pixels of most frames — apart; the Atrium model's hot spots (up to 45 fragments
/// per pixel under its foliage) still stand out in the last colour.
pub const OVERDRAW_TOP_MAX: u16 = 8;

/// The overdraw scale's top is the count that covers this share of the shaded pixels, so a
/// few silhouette pixels shaded by many thin triangles (10 where the rest are 1–3, in the
/// built-in scene at 4× MSAA) do not wash out every other colour; they share the top one.
pub const OVERDRAW_TOP_SHARE: f64 = 0.99;

/// Viridis at 9 evenly spaced points (matplotlib's `viridis`, CC0; the 9-class values
/// ColorBrewer-style tools list), interpolated linearly between them.
const VIRIDIS: [[u8; 3]; 9] = [
    [0x44, 0x01, 0x54],
    [0x47, 0x2d, 0x7b],
    [0x3b, 0x52, 0x8b],
    [0x2c, 0x72, 0x8e],
    [0x21, 0x91, 0x8c],
    [0x28, 0xae, 0x80],
    [0x5e, 0xc9, 0x62],
    [0xad, 0xdc, 0x30],
    [0xfd, 0xe7, 0x25],
];

/// The colour of `t` in `[0, 1]` (clamped).
pub fn viridis(t: f64) -> [u8; 3] {
    let t = if t.is_finite() { t.clamp(0.0, 1.0) } else { 0.0 };
    let position = t * (VIRIDIS.len() - 1) as f64;
    let i = (position.floor() as usize).min(VIRIDIS.len() - 2);
    let f = position - i as f64;
    std::array::from_fn(|c| {
        (VIRIDIS[i][c] as f64 + (VIRIDIS[i + 1][c] as f64 - VIRIDIS[i][c] as f64) * f).round() as u8
    })
}

/// `#rrggbb`.
pub fn hex([r, g, b]: [u8; 3]) -> String {
    format!("#{r:02x}{g:02x}{b:02x}")
}

/// A per-tile figure a heat map shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TileMetric {
    /// Polygon-list entries: how much geometry the tile reads back.
    ListEntries,
    /// Fragments the fragment shader ran for.
    FragmentsShaded,
    /// Bytes the tile's store ops wrote to memory.
    BytesStored,
}

impl TileMetric {
    pub const ALL: [TileMetric; 3] = [TileMetric::ListEntries, TileMetric::FragmentsShaded, TileMetric::BytesStored];

    /// The name in file names and HTML: `list-entries`.
    pub const fn name(self) -> &'static str {
        match self {
            TileMetric::ListEntries => "list-entries",
            TileMetric::FragmentsShaded => "fragments-shaded",
            TileMetric::BytesStored => "bytes-stored",
        }
    }

    /// The caption: `Polygon-list entries per tile`.
    pub const fn title(self) -> &'static str {
        match self {
            TileMetric::ListEntries => "Polygon-list entries per tile",
            TileMetric::FragmentsShaded => "Fragments shaded per tile",
            TileMetric::BytesStored => "Bytes stored per tile",
        }
    }

    pub fn value(self, tile: &TileStats) -> u64 {
        match self {
            TileMetric::ListEntries => tile.list_entries as u64,
            TileMetric::FragmentsShaded => tile.fragments_shaded as u64,
            TileMetric::BytesStored => tile.bytes_stored,
        }
    }

    /// Whether the figure is bytes (legends then show units).
    pub const fn is_bytes(self) -> bool {
        matches!(self, TileMetric::BytesStored)
    }
}

/// The per-tile figures of a pass, row-major; `None` for a pass without tiles (immediate
/// mode) or whose tile list does not match its grid.
pub fn tile_values(pass: &PassReport, metric: TileMetric) -> Option<Vec<u64>> {
    let expected = pass.tiles_x as usize * pass.tiles_y as usize;
    if pass.tiles.is_empty() || pass.tiles.len() != expected {
        return None;
    }
    Some(pass.tiles.iter().map(|t| metric.value(t)).collect())
}

/// A map's colour layer: uncoloured (transparent) where `t` is `None`.
fn overlay(width: u32, height: u32, mut t_of: impl FnMut(usize) -> Option<f64>) -> Rgba8Image {
    let alpha = (MAP_OPACITY * 255.0).round() as u8;
    let mut pixels = vec![0u8; width as usize * height as usize * 4];
    for (i, px) in pixels.chunks_exact_mut(4).enumerate() {
        if let Some(t) = t_of(i) {
            let [r, g, b] = viridis(t);
            px.copy_from_slice(&[r, g, b, alpha]);
        }
    }
    Rgba8Image { width, height, pixels }
}

/// The colour layer of a tile heat map: one pixel per tile, `tiles_x × tiles_y`.
pub fn tile_overlay(values: &[u64], tiles_x: u32, tiles_y: u32) -> Rgba8Image {
    let max = values.iter().copied().max().unwrap_or(0).max(1) as f64;
    overlay(tiles_x, tiles_y, |i| values.get(i).filter(|v| **v > 0).map(|v| *v as f64 / max))
}

/// The top of the overdraw scale for maps whose counts the scale must tell apart up to
/// `max_count`, within [`OVERDRAW_TOP_MIN`]..=[`OVERDRAW_TOP_MAX`].
pub fn overdraw_top(max_count: u16) -> u16 {
    max_count.clamp(OVERDRAW_TOP_MIN, OVERDRAW_TOP_MAX)
}

/// Where `count` fragments per pixel sits on a scale from 1 to `top`; `None` for 0.
pub fn overdraw_t(count: u16, top: u16) -> Option<f64> {
    (count > 0).then(|| (count.min(top) - 1) as f64 / (top.max(2) - 1) as f64)
}

/// The colour layer of an overdraw map: one pixel per pixel.
pub fn overdraw_overlay(map: &[u16], width: u32, height: u32, top: u16) -> Rgba8Image {
    overlay(width, height, |i| map.get(i).and_then(|c| overdraw_t(*c, top)))
}

fn overdraw_maps(report: &Report) -> impl Iterator<Item = &Vec<u16>> {
    report.columns.iter().flat_map(|c| &c.frame.passes).filter_map(|p| p.overdraw_map.as_ref())
}

/// The highest overdraw count of every map in the report.
pub fn report_overdraw_max(report: &Report) -> u16 {
    overdraw_maps(report).flat_map(|m| m.iter().copied()).max().unwrap_or(0)
}

/// The top of the overdraw scale every map of the report shares: the count that covers
/// [`OVERDRAW_TOP_SHARE`] of the shaded pixels of all of them, within
/// [`OVERDRAW_TOP_MIN`]..=[`OVERDRAW_TOP_MAX`].
pub fn report_overdraw_top(report: &Report) -> u16 {
    // Counts above the scale's limit all land in its last bucket.
    let last = OVERDRAW_TOP_MAX as usize + 1;
    let mut histogram = vec![0u64; last + 1];
    for count in overdraw_maps(report).flat_map(|m| m.iter()) {
        histogram[(*count as usize).min(last)] += 1;
    }
    let shaded: u64 = histogram[1..].iter().sum();
    let mut covered = 0;
    let mut top = 0;
    for (count, pixels) in histogram.iter().enumerate().skip(1) {
        covered += pixels;
        top = count;
        if covered as f64 >= shaded as f64 * OVERDRAW_TOP_SHARE {
            break;
        }
    }
    overdraw_top(top as u16)
}

/// `layer` laid over `background` dimmed to [`DIM`], at `width × height`: the layer is
/// stretched over `layer_width × layer_height` pixels from the top left (a tile grid may
/// reach past the picture's edge). Without a background (or one of another size), black.
fn composite(
    background: Option<&Rgba8Image>,
    width: u32,
    height: u32,
    layer: &Rgba8Image,
    layer_width: u32,
    layer_height: u32,
) -> Rgba8Image {
    let background =
        background.filter(|b| b.width == width && b.height == height && b.is_consistent()).map(|b| &b.pixels);
    let mut pixels = vec![0u8; width as usize * height as usize * 4];
    for y in 0..height as usize {
        let ly = (y as u64 * layer.height as u64 / layer_height.max(1) as u64) as usize;
        for x in 0..width as usize {
            let lx = (x as u64 * layer.width as u64 / layer_width.max(1) as u64) as usize;
            let i = (y * width as usize + x) * 4;
            let l = (ly * layer.width as usize + lx) * 4;
            let a = layer.pixels.get(l + 3).copied().unwrap_or(0) as f32 / 255.0;
            for c in 0..3 {
                let under = background.map_or(0.0, |b| b[i + c] as f32 * DIM);
                let over = layer.pixels.get(l + c).copied().unwrap_or(0) as f32;
                pixels[i + c] = (under * (1.0 - a) + over * a).round() as u8;
            }
            pixels[i + 3] = 255;
        }
    }
    Rgba8Image { width, height, pixels }
}

/// A tile heat map of `pass` over the dimmed `background`, at the pass's size; `None` for a
/// pass without tiles.
pub fn tile_heatmap(background: Option<&Rgba8Image>, pass: &PassReport, metric: TileMetric) -> Option<Rgba8Image> {
    let values = tile_values(pass, metric)?;
    let layer = tile_overlay(&values, pass.tiles_x, pass.tiles_y);
    Some(composite(
        background,
        pass.width,
        pass.height,
        &layer,
        pass.tiles_x * pass.tile_width,
        pass.tiles_y * pass.tile_height,
    ))
}

/// The overdraw map of `pass` over the dimmed `background`, colours on a scale to `top`;
/// `None` when the pass recorded no overdraw map.
pub fn overdraw_heatmap(background: Option<&Rgba8Image>, pass: &PassReport, top: u16) -> Option<Rgba8Image> {
    let map = pass.overdraw_map.as_ref()?;
    if map.len() != pass.width as usize * pass.height as usize {
        return None;
    }
    let layer = overdraw_overlay(map, pass.width, pass.height, top);
    Some(composite(background, pass.width, pass.height, &layer, pass.width, pass.height))
}

/// PNG-encodes an image.
///
/// # Errors
/// An image whose pixel array does not match its size.
pub fn png_bytes(image: &Rgba8Image) -> Result<Vec<u8>, image::ImageError> {
    use image::ImageEncoder;
    let mut out = Vec::new();
    image::codecs::png::PngEncoder::new(&mut out).write_image(
        &image.pixels,
        image.width,
        image.height,
        image::ExtendedColorType::Rgba8,
    )?;
    Ok(out)
}

/// A file-name-safe form of a label: lower-case letters, digits and `-`.
fn slug(label: &str) -> String {
    let mut out = String::new();
    for c in label.chars() {
        if c.is_ascii_alphanumeric() {
            out.push(c.to_ascii_lowercase());
        } else if !out.ends_with('-') {
            out.push('-');
        }
    }
    let out = out.trim_matches('-').to_string();
    if out.is_empty() { "column".to_string() } else { out }
}

/// Writes every heat map of the report into `dir` (created if missing): for each column and
/// pass, `<label>-pass<N>-{list-entries,fragments-shaded,bytes-stored}.png` (tilers) and
/// `<label>-pass<N>-overdraw.png` (when an overdraw map was recorded). Passes the size of
/// the picture are drawn over it; others over black. Returns the files written.
///
/// # Errors
/// The directory cannot be created or a file cannot be written, naming the path. Each file is
/// written beside its target and renamed into place, so a failure leaves no half-written map.
pub fn write_heatmaps(report: &Report, dir: &Path) -> std::io::Result<Vec<PathBuf>> {
    let named = |path: &Path, e: &dyn std::fmt::Display| std::io::Error::other(format!("{}: {e}", path.display()));
    std::fs::create_dir_all(dir).map_err(|e| named(dir, &e))?;
    let top = report_overdraw_top(report);
    let mut written = Vec::new();
    let mut used = std::collections::HashSet::new();
    for (index, column) in report.columns.iter().enumerate() {
        let mut stem = slug(&column.label);
        if !used.insert(stem.clone()) {
            stem = format!("{stem}-{index}");
            used.insert(stem.clone());
        }
        for (pass_index, pass) in column.frame.passes.iter().enumerate() {
            let mut maps: Vec<(&str, Rgba8Image)> = TileMetric::ALL
                .iter()
                .filter_map(|m| Some((m.name(), tile_heatmap(Some(&column.image), pass, *m)?)))
                .collect();
            if let Some(map) = overdraw_heatmap(Some(&column.image), pass, top) {
                maps.push(("overdraw", map));
            }
            for (name, map) in maps {
                let path = dir.join(format!("{stem}-pass{pass_index}-{name}.png"));
                let png = png_bytes(&map).map_err(|e| named(&path, &e))?;
                tiler_io::write_atomic(&path, &png).map_err(|e| std::io::Error::other(e.to_string()))?;
                written.push(path);
            }
        }
    }
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn viridis_ends_and_middle() {
        assert_eq!(viridis(0.0), VIRIDIS[0]);
        assert_eq!(viridis(1.0), VIRIDIS[8]);
        assert_eq!(viridis(0.5), VIRIDIS[4]);
        assert_eq!(viridis(f64::NAN), VIRIDIS[0]);
        assert_eq!(hex(VIRIDIS[8]), "#fde725");
    }

    #[test]
    fn overdraw_scale_runs_from_one_to_the_top() {
        assert_eq!(overdraw_top(1), OVERDRAW_TOP_MIN);
        assert_eq!(overdraw_top(1000), OVERDRAW_TOP_MAX);
        assert_eq!(overdraw_t(0, 4), None);
        assert_eq!(overdraw_t(1, 4), Some(0.0));
        assert_eq!(overdraw_t(4, 4), Some(1.0));
        assert_eq!(overdraw_t(9, 4), Some(1.0));
    }

    #[test]
    fn a_tile_layer_stretches_over_the_picture() {
        // Two tiles of 2×1 pixels over a 3×1 picture: the grid reaches past the right edge.
        let layer = tile_overlay(&[0, 5], 2, 1);
        assert_eq!(layer.pixels[3], 0, "an empty tile is uncoloured");
        let background = Rgba8Image { width: 3, height: 1, pixels: vec![200; 12] };
        let out = composite(Some(&background), 3, 1, &layer, 4, 1);
        // Pixels 0 and 1 are the empty first tile: the picture, dimmed.
        assert_eq!(out.pixels[..8], [70, 70, 70, 255, 70, 70, 70, 255], "dimmed to {DIM}");
        // Pixel 2 is in the second tile, the maximum: the last viridis colour at MAP_OPACITY.
        let a = (MAP_OPACITY * 255.0).round() / 255.0;
        assert_eq!(out.pixels[8], (70.0 * (1.0 - a) + 253.0 * a).round() as u8);
    }

    #[test]
    fn slugs() {
        assert_eq!(slug("tbr-per-tile-vertex"), "tbr-per-tile-vertex");
        assert_eq!(slug("My GPU (imr)"), "my-gpu-imr");
        assert_eq!(slug("///"), "column");
    }
}
