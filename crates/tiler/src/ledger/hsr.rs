//! Why the TBDR backend rendered fragments in submission order instead of waiting for
//! hidden-surface removal (`depth::hsr` decides; the counters here record it).

use serde::Serialize;

/// Why a draw's fragments are rendered in submission order instead of waiting for HSR.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum HsrFallback {
    /// The fragment shader may `discard` (seed 000 §23.7, seed 002 "Depth Testing").
    Discard,
    /// Blending reads what is behind (seed 000 §23.7, §23.8).
    Blending,
    /// The fragment shader writes depth (seed 002: `gl_FragDepth`).
    ShaderDepth,
    /// Alpha-to-coverage changes coverage after shading (seed 000 §23.7).
    AlphaToCoverage,
    /// The fragment shader writes the sample mask (seed 000 §23.7, seed 002: `gl_SampleMask`).
    SampleMask,
    /// Some but not all channels are written, so the result mixes surfaces.
    PartialWriteMask,
    /// The shader has side effects and must run for every fragment (seed 002: storage writes).
    SideEffects,
    /// The shader reads the attachments it writes (pixel-local storage): order matters.
    PixelLocalRead,
}

/// Fragments rendered in submission order on the TBDR backend, by reason.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct HsrFallbacks {
    pub discard: u64,
    pub blending: u64,
    pub shader_depth: u64,
    pub alpha_to_coverage: u64,
    pub sample_mask: u64,
    pub partial_write_mask: u64,
    pub side_effects: u64,
    pub pixel_local_read: u64,
}

impl HsrFallbacks {
    pub fn add(&mut self, reason: HsrFallback, fragments: u64) {
        *match reason {
            HsrFallback::Discard => &mut self.discard,
            HsrFallback::Blending => &mut self.blending,
            HsrFallback::ShaderDepth => &mut self.shader_depth,
            HsrFallback::AlphaToCoverage => &mut self.alpha_to_coverage,
            HsrFallback::SampleMask => &mut self.sample_mask,
            HsrFallback::PartialWriteMask => &mut self.partial_write_mask,
            HsrFallback::SideEffects => &mut self.side_effects,
            HsrFallback::PixelLocalRead => &mut self.pixel_local_read,
        } += fragments;
    }

    pub fn total(&self) -> u64 {
        self.discard
            + self.blending
            + self.shader_depth
            + self.alpha_to_coverage
            + self.sample_mask
            + self.partial_write_mask
            + self.side_effects
            + self.pixel_local_read
    }

    pub fn merge(&mut self, o: &HsrFallbacks) {
        self.discard += o.discard;
        self.blending += o.blending;
        self.shader_depth += o.shader_depth;
        self.alpha_to_coverage += o.alpha_to_coverage;
        self.sample_mask += o.sample_mask;
        self.partial_write_mask += o.partial_write_mask;
        self.side_effects += o.side_effects;
        self.pixel_local_read += o.pixel_local_read;
    }
}
