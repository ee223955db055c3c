//! Sample locations within a pixel: Vulkan's standard locations (`standardSampleLocations`,
//! the same as Direct3D's), origin at the pixel's top-left corner, y down, in sub-pixels.
//! With one sample the location is the pixel centre (0.5, 0.5).

use super::fixed::SUBPIXEL_SCALE;

/// Positions in 1/16 pixel, as the Vulkan specification tabulates them.
const STANDARD_1: [(i32, i32); 1] = [(8, 8)];
const STANDARD_2: [(i32, i32); 2] = [(12, 12), (4, 4)];
const STANDARD_4: [(i32, i32); 4] = [(6, 2), (14, 6), (2, 10), (10, 14)];
const STANDARD_8: [(i32, i32); 8] = [(9, 5), (7, 11), (13, 9), (5, 3), (3, 13), (1, 7), (11, 15), (15, 1)];

/// The most samples per pixel tiler renders.
pub const MAX_SAMPLES: usize = 8;

/// The sample locations of one sample count, in sub-pixels from the pixel's corner.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SampleLocations {
    count: usize,
    positions: [(i32, i32); MAX_SAMPLES],
}

impl SampleLocations {
    /// The standard locations for 1, 2, 4 or 8 samples.
    ///
    /// # Panics
    /// For any other count (sample counts are validated when images are created).
    pub fn standard(samples: u32) -> SampleLocations {
        let table: &[(i32, i32)] = match samples {
            1 => &STANDARD_1,
            2 => &STANDARD_2,
            4 => &STANDARD_4,
            8 => &STANDARD_8,
            _ => unreachable!("unsupported sample count {samples}"),
        };
        let scale = SUBPIXEL_SCALE / 16;
        let mut positions = [(0, 0); MAX_SAMPLES];
        for (p, &(x, y)) in positions.iter_mut().zip(table) {
            *p = (x * scale, y * scale);
        }
        SampleLocations { count: table.len(), positions }
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
    pub fn hull(&self) -> (i32, i32, i32, i32) {
        let xs = self.iter().map(|p| p.0);
        let ys = self.iter().map(|p| p.1);
        (xs.clone().min().unwrap(), ys.clone().min().unwrap(), xs.max().unwrap(), ys.max().unwrap())
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
}
