//! Why rendering failed.

use thiserror::Error;

/// Errors of the renderer. None of them is a panic: a machine without any graphics adapter gets
/// [`RenderError::NoAdapter`] with the list of backends that were tried.
#[derive(Debug, Error)]
pub enum RenderError {
    /// No graphics adapter, not even a software one, could be found.
    #[error(
        "no graphics adapter found (backends tried: {backends}; {hint}). On a machine without a \
         GPU install Mesa's software renderers (Debian: `apt-get install mesa-vulkan-drivers \
         libvulkan1 libegl1 libgl1-mesa-dri`), or choose a backend with WGPU_BACKEND=vulkan|gl"
    )]
    NoAdapter {
        /// The backends that were enabled.
        backends: String,
        /// What wgpu said.
        hint: String,
    },
    /// The adapter refused to create a device. (The cause is in the message, not the error's
    /// source: a chain printed whole, `{:#}`, would tell it twice.)
    #[error("the graphics adapter \"{adapter}\" refused to create a device: {cause}")]
    Device {
        /// The adapter's name.
        adapter: String,
        /// Why.
        cause: wgpu::RequestDeviceError,
    },
    /// The GPU reported an error (validation, out of memory, lost device).
    #[error("the GPU reported an error: {0}")]
    Gpu(String),
    /// Reading the rendered image back failed.
    #[error("reading the rendered image back failed: {0}")]
    Readback(String),
    /// The image size is zero or larger than the adapter allows.
    #[error("image size {width}×{height} is not possible (each side from 1 to {max} pixels)")]
    Size {
        /// Requested width.
        width: u32,
        /// Requested height.
        height: u32,
        /// The adapter's largest 2D texture side.
        max: u32,
    },
    /// The image is more pixels than the adapter can read back at once.
    #[error(
        "image size {width}×{height} is not possible: its {megabytes:.0} MB of pixels exceed \
         the {max_megabytes:.0} MB the adapter reads back at once (at most about {side}×{side}; \
         render a smaller image)"
    )]
    TooLarge {
        /// Requested width.
        width: u32,
        /// Requested height.
        height: u32,
        /// The read-back buffer it needs, MB.
        megabytes: f64,
        /// The adapter's largest buffer, MB.
        max_megabytes: f64,
        /// The side of the largest square image that fits.
        side: u32,
    },
    /// A draw list is malformed (an index out of range, scalars of the wrong length...).
    #[error("invalid draw list: {0}")]
    InvalidInput(String),
}
