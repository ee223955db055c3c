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
