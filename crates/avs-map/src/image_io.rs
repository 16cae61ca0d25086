//! Reading images with bounded memory: the one home of every image read (map images and
//! ground-truth segmentations).
//!
//! A PNG of a few hundred kilobytes can declare 20000 × 20000 pixels (zeros compress about
//! 1000:1), and decoding it first and checking the size afterwards allocated 400 MB for the
//! pixels and several GB more for the copies and label arrays built from them. [`open_image`]
//! therefore reads only the header first and refuses an image of more than
//! [`MAX_IMAGE_PIXELS`] pixels before any pixel buffer exists, then decodes with the `image`
//! crate's allocation limit set to [`MAX_DECODE_BYTES`].
//!
//! Why these numbers: an image becomes an occupancy grid of one cell per pixel, and grids are
//! capped at [`crate::grid::MAX_CELLS`] (64 M cells: 8000 × 8000, a 400 m × 400 m floor at
//! 5 cm per cell — larger than any building map we know of; the benchmark maps are about
//! 1000 × 1000). The decoder's limit is that many pixels at the widest format the PNG and PNM
//! decoders produce (RGBA, 16 bits a channel: 8 bytes), so every image within the pixel limit
//! decodes and nothing else is allocated by the decoder.

use crate::grid::MAX_CELLS;
use image::{DynamicImage, ImageReader, Limits};
use std::path::Path;

/// Most pixels of an image avs reads: [`crate::grid::MAX_CELLS`].
pub const MAX_IMAGE_PIXELS: u64 = MAX_CELLS as u64;

/// Most bytes the decoder may allocate: [`MAX_IMAGE_PIXELS`] at 8 bytes a pixel (512 MB).
pub const MAX_DECODE_BYTES: u64 = MAX_IMAGE_PIXELS * 8;

/// Why an image could not be read.
#[derive(Debug, thiserror::Error)]
pub enum ImageReadError {
    /// The file could not be opened or read.
    #[error("cannot read the file: {0}")]
    Io(#[from] std::io::Error),
    /// The header declares more than [`MAX_IMAGE_PIXELS`] pixels.
    #[error("the image declares {width} × {height} pixels, more than the limit of {limit}; expected a smaller image (or a coarser map)")]
    TooLarge {
        /// Declared width in pixels.
        width: u32,
        /// Declared height in pixels.
        height: u32,
        /// [`MAX_IMAGE_PIXELS`].
        limit: u64,
    },
    /// The decoder failed (unknown format, corrupt data, or its allocation limit).
    #[error(transparent)]
    Decode(#[from] image::ImageError),
}

/// Open and decode the image at `path` (format from the extension, else from the content)
/// within the limits of the module docs: the size is checked from the header before decoding.
pub fn open_image(path: &Path) -> Result<DynamicImage, ImageReadError> {
    let (width, height) = ImageReader::open(path)?
        .with_guessed_format()?
        .into_dimensions()?;
    if u64::from(width) * u64::from(height) > MAX_IMAGE_PIXELS {
        return Err(ImageReadError::TooLarge {
            width,
            height,
            limit: MAX_IMAGE_PIXELS,
        });
    }
    let mut reader = ImageReader::open(path)?.with_guessed_format()?;
    let mut limits = Limits::default();
    limits.max_alloc = Some(MAX_DECODE_BYTES);
    reader.limits(limits);
    Ok(reader.decode()?)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// Standard CRC-32 (PNG chunks).
    fn crc32(bytes: &[u8]) -> u32 {
        let mut c = 0xffff_ffffu32;
        for &b in bytes {
            c ^= u32::from(b);
            for _ in 0..8 {
                c = if c & 1 != 0 {
                    0xedb8_8320 ^ (c >> 1)
                } else {
                    c >> 1
                };
            }
        }
        !c
    }

    /// A small valid PNG whose header is then rewritten to declare `w × h` pixels (the pixel
    /// data stays a few bytes: only a decoder that believes the header allocates for it).
    pub(crate) fn png_declaring(w: u32, h: u32) -> Vec<u8> {
        let mut out = std::io::Cursor::new(Vec::new());
        image::GrayImage::from_pixel(4, 4, image::Luma([255]))
            .write_to(&mut out, image::ImageFormat::Png)
            .unwrap();
        let mut png = out.into_inner();
        // Signature (8), IHDR length (4), "IHDR" (4), width, height, …, CRC over type + data.
        png[16..20].copy_from_slice(&w.to_be_bytes());
        png[20..24].copy_from_slice(&h.to_be_bytes());
        let crc = crc32(&png[12..29]);
        png[29..33].copy_from_slice(&crc.to_be_bytes());
        png
    }

    #[test]
    fn a_huge_declared_size_is_refused_from_the_header() {
        let dir = std::env::temp_dir().join(format!("avs-image-io-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let huge = dir.join("huge.png");
        std::fs::write(&huge, png_declaring(20000, 20000)).unwrap();
        match open_image(&huge) {
            Err(ImageReadError::TooLarge { width, height, .. }) => {
                assert_eq!((width, height), (20000, 20000))
            }
            other => panic!("expected TooLarge, got {other:?}"),
        }
        // The same file at its real size decodes: the patching itself is sound.
        let small = dir.join("small.png");
        std::fs::write(&small, png_declaring(4, 4)).unwrap();
        let img = open_image(&small).unwrap();
        assert_eq!((img.width(), img.height()), (4, 4));
        let e = open_image(&dir.join("missing.png")).unwrap_err();
        assert!(matches!(e, ImageReadError::Io(_)), "{e:?}");
        std::fs::remove_dir_all(&dir).ok();
    }

    /// Issue 18 reproducer: `avs segment --truth` on a small PNG declaring 20000 × 20000 pixels
    /// allocated 6 GB and aborted; the map loader had no check before decoding either. Both
    /// readers now refuse it from the header, with the size in the error.
    #[test]
    fn truth_and_map_images_declaring_huge_sizes_are_clean_errors() {
        let dir = std::env::temp_dir().join(format!("avs-image-limits-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let png = dir.join("truth.png");
        std::fs::write(&png, png_declaring(20000, 20000)).unwrap();
        let e = crate::metrics::load_truth_image(&png).unwrap_err();
        let text = e.to_string();
        assert!(
            text.contains("20000 × 20000 pixels, more than the limit of 64000000"),
            "{text}"
        );
        let yaml = dir.join("map.yaml");
        std::fs::write(
            &yaml,
            "image: truth.png\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n",
        )
        .unwrap();
        let e = crate::grid::OccupancyGrid::from_map_server_yaml(&yaml).unwrap_err();
        assert!(
            matches!(&e, crate::grid::MapError::Image { message, .. } if message.contains("20000 × 20000")),
            "{e:?}"
        );
        std::fs::remove_dir_all(&dir).ok();
    }
}
