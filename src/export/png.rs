//! PNG files written atomically: encoded in memory, written to a temporary file beside the
//! target, then renamed over it, so that a reader never sees half an image.

use image::{ImageFormat, RgbaImage};
use std::io::Cursor;
use std::path::Path;

/// Encodes `image` as PNG bytes.
pub fn png_bytes(image: &RgbaImage) -> std::io::Result<Vec<u8>> {
    let mut bytes = Vec::new();
    image
        .write_to(&mut Cursor::new(&mut bytes), ImageFormat::Png)
        .map_err(std::io::Error::other)?;
    Ok(bytes)
}

/// Writes `image` to `path` as PNG (temporary file, then rename). Creates missing parent folders.
pub fn write_png_atomic(path: &Path, image: &RgbaImage) -> std::io::Result<()> {
    write_bytes_atomic(path, &png_bytes(image)?)
}

/// Writes `bytes` to `path` through a temporary file beside it and a rename, so that a reader
/// never sees half a file. Creates missing parent folders.
pub fn write_bytes_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    std::fs::create_dir_all(dir)?;
    let name = path
        .file_name()
        .ok_or_else(|| std::io::Error::other(format!("{} is not a file name", path.display())))?;
    let tmp = dir.join(format!(
        ".{}.{}.tmp",
        name.to_string_lossy(),
        std::process::id()
    ));
    std::fs::write(&tmp, bytes)?;
    std::fs::rename(&tmp, path).inspect_err(|_| {
        let _ = std::fs::remove_file(&tmp);
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_no_leftovers() {
        let dir = std::env::temp_dir().join(format!("prehensile-png-{}", std::process::id()));
        let path = dir.join("sub").join("a.png");
        let mut img = RgbaImage::new(3, 2);
        img.put_pixel(2, 1, image::Rgba([10, 20, 30, 255]));
        write_png_atomic(&path, &img).unwrap();
        let back = image::open(&path).unwrap().to_rgba8();
        assert_eq!(back.get_pixel(2, 1).0, [10, 20, 30, 255]);
        assert_eq!(
            std::fs::read_dir(path.parent().unwrap()).unwrap().count(),
            1
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
