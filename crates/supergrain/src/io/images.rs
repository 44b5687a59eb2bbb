//! Pictures to files: PNG frames and GIF animations, encoded by the `image` crate.

use std::io::Write;

use image::codecs::gif::{GifEncoder, Repeat};
use image::codecs::png::PngEncoder;
use image::{Delay, ExtendedColorType, Frame, ImageEncoder, ImageError, RgbaImage};
use tiny_skia::Pixmap;

/// A pixmap (premultiplied) as a plain RGBA image.
pub fn to_rgba_image(pixmap: &Pixmap) -> RgbaImage {
    let data = pixmap
        .pixels()
        .iter()
        .flat_map(|p| {
            let c = p.demultiply();
            [c.red(), c.green(), c.blue(), c.alpha()]
        })
        .collect();
    RgbaImage::from_raw(pixmap.width(), pixmap.height(), data).expect("sizes agree")
}

/// Writes a pixmap as PNG.
pub fn write_png(pixmap: &Pixmap, out: impl Write) -> Result<(), ImageError> {
    let image = to_rgba_image(pixmap);
    PngEncoder::new(out).write_image(
        image.as_raw(),
        image.width(),
        image.height(),
        ExtendedColorType::Rgba8,
    )
}

/// An animated GIF written frame by frame, looping for ever.
pub struct GifWriter<W: Write> {
    encoder: GifEncoder<W>,
    delay: Delay,
}

impl<W: Write> GifWriter<W> {
    /// A GIF at `fps` frames per second. `speed` trades colour quantisation quality for time
    /// (1 best and slowest, 30 fastest; the `image` crate's scale).
    pub fn new(out: W, fps: f64, speed: i32) -> Result<Self, ImageError> {
        let mut encoder = GifEncoder::new_with_speed(out, speed.clamp(1, 30));
        encoder.set_repeat(Repeat::Infinite)?;
        let ms = (1000.0 / fps.max(0.1)).round() as u32;
        Ok(GifWriter {
            encoder,
            delay: Delay::from_numer_denom_ms(ms, 1),
        })
    }

    pub fn push(&mut self, pixmap: &Pixmap) -> Result<(), ImageError> {
        let frame = Frame::from_parts(to_rgba_image(pixmap), 0, 0, self.delay);
        self.encoder.encode_frame(frame)
    }
}
