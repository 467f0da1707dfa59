//! Files read whole, up to a size: a scene named `/dev/zero`, or a file far larger than its kind
//! ever is, is refused with its size said instead of filling the memory.

use std::io::Read;
use std::path::Path;

/// The bytes of `path`, refused (an `InvalidData` error saying so) beyond `limit` bytes.
pub fn read_at_most(path: &Path, limit: u64) -> std::io::Result<Vec<u8>> {
    let file = std::fs::File::open(path)?;
    let mut bytes = Vec::new();
    file.take(limit.saturating_add(1)).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!(
                "it is larger than {} MB, more than a file of its kind holds",
                limit / 1_000_000
            ),
        ));
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_beyond_the_limit_is_refused_and_one_within_is_read() {
        let dir = std::env::temp_dir().join(format!("prehensile-read-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("f");
        std::fs::write(&path, vec![7u8; 2_000_001]).unwrap();
        let err = read_at_most(&path, 2_000_000).unwrap_err();
        assert_eq!(err.kind(), std::io::ErrorKind::InvalidData);
        assert!(err.to_string().contains("larger than 2 MB"), "{err}");
        assert_eq!(read_at_most(&path, 2_000_001).unwrap().len(), 2_000_001);
        // An endless source stops at the limit.
        #[cfg(unix)]
        assert!(read_at_most(Path::new("/dev/zero"), 1_000_000).is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
