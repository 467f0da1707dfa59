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
/// never sees half a file. Creates missing parent folders. A symbolic link is written through
/// (the file it names is replaced, the link stays); a device or a pipe (`/dev/null`, a FIFO)
/// is written to as it is — renaming over it would put a plain file in its place; a folder is
/// refused.
pub fn write_bytes_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let resolved;
    let path = match std::fs::symlink_metadata(path) {
        Ok(meta) if meta.file_type().is_symlink() => {
            resolved = link_target(path)?;
            resolved.as_path()
        }
        _ => path,
    };
    if let Ok(meta) = std::fs::metadata(path) {
        if meta.is_dir() {
            return Err(std::io::Error::other(format!(
                "{} is a folder: give a file's path",
                path.display()
            )));
        }
        if !meta.is_file() {
            // A device or a pipe: written to in place (nothing to rename over).
            return std::fs::write(path, bytes);
        }
    }
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

/// The path a symbolic link `link` finally names (followed through chains of links; a link to
/// a path that does not exist yet names that path).
fn link_target(link: &Path) -> std::io::Result<std::path::PathBuf> {
    if let Ok(found) = std::fs::canonicalize(link) {
        return Ok(found);
    }
    let mut at = link.to_path_buf();
    for _ in 0..40 {
        match std::fs::symlink_metadata(&at) {
            Ok(meta) if meta.file_type().is_symlink() => {
                let to = std::fs::read_link(&at)?;
                at = match at.parent() {
                    Some(dir) if to.is_relative() => dir.join(to),
                    _ => to,
                };
            }
            _ => return Ok(at),
        }
    }
    Err(std::io::Error::other(format!(
        "{}: too many levels of symbolic links",
        link.display()
    )))
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

    /// A link is written through (the link stays, the file it names is the new one); a pipe is
    /// written to in place, not replaced by a plain file (`--out /dev/null` once turned the
    /// machine's /dev/null into a file); a folder is refused and left as it was.
    #[cfg(unix)]
    #[test]
    fn links_pipes_and_folders_are_not_replaced() {
        use std::os::unix::fs::FileTypeExt;
        let dir = std::env::temp_dir().join(format!("prehensile-out-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let target = dir.join("real.glb");
        std::fs::write(&target, b"old").unwrap();
        let link = dir.join("link.glb");
        std::os::unix::fs::symlink("real.glb", &link).unwrap();
        write_bytes_atomic(&link, b"new").unwrap();
        assert!(std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(std::fs::read(&target).unwrap(), b"new");
        // A dangling link names the file to make.
        let dangling = dir.join("dangling.png");
        std::os::unix::fs::symlink("made.png", &dangling).unwrap();
        write_bytes_atomic(&dangling, b"made").unwrap();
        assert_eq!(std::fs::read(dir.join("made.png")).unwrap(), b"made");
        // A FIFO, read by another thread while written.
        let fifo = dir.join("pipe");
        let made = std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .is_ok_and(|s| s.success());
        if made {
            let reader = {
                let fifo = fifo.clone();
                std::thread::spawn(move || std::fs::read(fifo).unwrap())
            };
            write_bytes_atomic(&fifo, b"through the pipe").unwrap();
            assert_eq!(reader.join().unwrap(), b"through the pipe");
            assert!(std::fs::symlink_metadata(&fifo)
                .unwrap()
                .file_type()
                .is_fifo());
        }
        let folder = dir.join("folder.png");
        std::fs::create_dir_all(&folder).unwrap();
        let err = write_bytes_atomic(&folder, b"x").unwrap_err();
        assert!(err.to_string().contains("is a folder"), "{err}");
        assert!(folder.is_dir());
        // Nothing left behind but what was asked for.
        let mut left: Vec<String> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        left.sort();
        let mut expected = vec![
            "dangling.png",
            "folder.png",
            "link.glb",
            "made.png",
            "real.glb",
        ];
        if made {
            expected.push("pipe");
            expected.sort();
        }
        assert_eq!(left, expected);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
