//! How well a frame is drawn: anti-aliased and finely shadowed, or a draft for a view that
//! changes fast.

use super::pipelines::MSAA_SAMPLES;

/// How a frame is drawn.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Quality {
    /// Anti-aliased ([`MSAA_SAMPLES`] samples per pixel): the frame shown at rest, images.
    #[default]
    Full,
    /// One sample per pixel, one shadow tap, fewer samples of the ground's contact occlusion
    /// (`globals::LightSampling`), the same shading: a view that changes fast (a pose dragged,
    /// the camera orbiting). On a software renderer (llvmpipe) the samples and taps are most of a
    /// small frame's cost (docs/performance.md).
    Draft,
}

impl Quality {
    /// Samples per pixel of the frame.
    pub fn samples(self) -> u32 {
        match self {
            Quality::Full => MSAA_SAMPLES,
            Quality::Draft => 1,
        }
    }
}
