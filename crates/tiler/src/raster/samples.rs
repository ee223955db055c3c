//! Sample locations within a pixel: Vulkan's standard locations (`standardSampleLocations`,
//! the same as Direct3D's), origin at the pixel's top-left corner, y down, in sub-pixels.
//! With one sample the location is the pixel centre (0.5, 0.5).

use super::fixed::SUBPIXEL_SCALE;

/// Positions in 1/16 pixel, as the Vulkan specification tabulates them.
const STANDARD_1: [(i32, i32); 1] = [(8, 8)];
const STANDARD_2: [(i32, i32); 2] = [(12, 12), (4, 4)];
const STANDARD_4: [(i32, i32); 4] = [(6, 2), (14, 6), (2, 10), (10, 14)];
const STANDARD_8: [(i32, i32); 8] = [(9, 5), (7, 11), (13, 9), (5, 3), (3, 13), (1, 7), (11, 15), (15, 1)];
const STANDARD_16: [(i32, i32); 16] = [
    (9, 9),
    (7, 5),
    (5, 10),
    (12, 7),
    (3, 6),
    (10, 13),
    (13, 11),
    (11, 3),
    (6, 14),
    (8, 1),
    (4, 2),
    (2, 12),
    (0, 8),
    (15, 4),
    (14, 15),
    (1, 0),
];

/// Which way up a pass's sample locations are laid out in its pixels.
///
/// The standard locations are tabulated from the pixel's top-left corner, y down, for images
/// stored top row first. An OpenGL implementation that stores a framebuffer object bottom row
/// first (GL's window coordinates, y up) and uses the same table there — llvmpipe does — puts
/// them mirrored vertically in an image stored top row first, as tiler stores every image.
/// `LowerLeft` is that mirror: each location `(x, y)` becomes `(x, 1 − y)`. Sample indices keep
/// their order.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SampleOrigin {
    /// The standard table as it is (Vulkan, Direct3D; a GL window surface).
    #[default]
    UpperLeft,
    /// The standard table mirrored vertically (a GL framebuffer object on llvmpipe).
    LowerLeft,
}

/// The most samples per pixel tiler renders.
pub const MAX_SAMPLES: usize = 16;

/// The sample locations of one sample count, in sub-pixels from the pixel's corner.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SampleLocations {
    count: usize,
    positions: [(i32, i32); MAX_SAMPLES],
    /// [`SampleLocations::hull`], worked out once (every primitive's coverage asks for it).
    hull: (i32, i32, i32, i32),
}

impl SampleLocations {
    /// The standard locations for 1, 2, 4, 8 or 16 samples.
    ///
    /// # Panics
    /// For any other count (sample counts are validated when images are created).
    pub fn standard(samples: u32) -> SampleLocations {
        let table: &[(i32, i32)] = match samples {
            1 => &STANDARD_1,
            2 => &STANDARD_2,
            4 => &STANDARD_4,
            8 => &STANDARD_8,
            16 => &STANDARD_16,
            _ => unreachable!("unsupported sample count {samples}"),
        };
        let scale = SUBPIXEL_SCALE / 16;
        let mut positions = [(0, 0); MAX_SAMPLES];
        for (p, &(x, y)) in positions.iter_mut().zip(table) {
            *p = (x * scale, y * scale);
        }
        let positions = &positions[..table.len()];
        let xs = positions.iter().map(|p| p.0);
        let ys = positions.iter().map(|p| p.1);
        let hull = (xs.clone().min().unwrap(), ys.clone().min().unwrap(), xs.max().unwrap(), ys.max().unwrap());
        let mut all = [(0, 0); MAX_SAMPLES];
        all[..table.len()].copy_from_slice(positions);
        SampleLocations { count: table.len(), positions: all, hull }
    }

    /// The standard locations for `samples`, laid out from `origin`.
    ///
    /// # Panics
    /// As [`SampleLocations::standard`].
    pub fn new(samples: u32, origin: SampleOrigin) -> SampleLocations {
        let mut locations = SampleLocations::standard(samples);
        if origin == SampleOrigin::LowerLeft {
            for p in &mut locations.positions[..locations.count] {
                p.1 = SUBPIXEL_SCALE - p.1;
            }
            let (x0, y0, x1, y1) = locations.hull;
            locations.hull = (x0, SUBPIXEL_SCALE - y1, x1, SUBPIXEL_SCALE - y0);
        }
        locations
    }

    pub fn count(&self) -> usize {
        self.count
    }

    /// Sub-pixel offset of sample `i` from its pixel's corner.
    #[inline(always)]
    pub fn offset(&self, i: usize) -> (i32, i32) {
        self.positions[i]
    }

    pub fn iter(&self) -> impl Iterator<Item = (i32, i32)> + Clone + '_ {
        self.positions[..self.count].iter().copied()
    }

    /// The smallest and largest x and y offsets over all samples: the sample hull of a pixel.
    #[inline]
    pub fn hull(&self) -> (i32, i32, i32, i32) {
        self.hull
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn standard_four_sample_pattern() {
        let s = SampleLocations::standard(4);
        let pixels: Vec<(f32, f32)> = s.iter().map(|(x, y)| (x as f32 / 256.0, y as f32 / 256.0)).collect();
        assert_eq!(pixels, vec![(0.375, 0.125), (0.875, 0.375), (0.125, 0.625), (0.625, 0.875)]);
        assert_eq!(SampleLocations::standard(1).offset(0), (128, 128));
    }

    #[test]
    fn lower_left_locations_mirror_the_standard_ones_vertically() {
        let s = SampleLocations::new(4, SampleOrigin::LowerLeft);
        let pixels: Vec<(f32, f32)> = s.iter().map(|(x, y)| (x as f32 / 256.0, y as f32 / 256.0)).collect();
        assert_eq!(pixels, vec![(0.375, 0.875), (0.875, 0.625), (0.125, 0.375), (0.625, 0.125)]);
        let hull = |s: SampleLocations| {
            let (xs, ys): (Vec<i32>, Vec<i32>) = s.iter().unzip();
            (*xs.iter().min().unwrap(), *ys.iter().min().unwrap(), *xs.iter().max().unwrap(), *ys.iter().max().unwrap())
        };
        for samples in [1, 2, 4, 8, 16] {
            let s = SampleLocations::new(samples, SampleOrigin::LowerLeft);
            assert_eq!(s.hull(), hull(s), "{samples} samples");
        }
        assert_eq!(SampleLocations::new(1, SampleOrigin::LowerLeft), SampleLocations::standard(1));
    }

    #[test]
    fn standard_sixteen_sample_pattern() {
        // The Vulkan specification's table (and Direct3D's 16× pattern), in pixels.
        let expected = [
            (0.5625, 0.5625),
            (0.4375, 0.3125),
            (0.3125, 0.625),
            (0.75, 0.4375),
            (0.1875, 0.375),
            (0.625, 0.8125),
            (0.8125, 0.6875),
            (0.6875, 0.1875),
            (0.375, 0.875),
            (0.5, 0.0625),
            (0.25, 0.125),
            (0.125, 0.75),
            (0.0, 0.5),
            (0.9375, 0.25),
            (0.875, 0.9375),
            (0.0625, 0.0),
        ];
        let s = SampleLocations::standard(16);
        assert_eq!(s.count(), 16);
        let pixels: Vec<(f32, f32)> = s.iter().map(|(x, y)| (x as f32 / 256.0, y as f32 / 256.0)).collect();
        assert_eq!(pixels, expected);
        // The hull reaches both pixel edges on the left and top: (0, 0.5) and (0.0625, 0).
        assert_eq!(s.hull(), (0, 0, 15 * 16, 15 * 16));
    }
}
