//! Reading the program's VTU files back in the tests: a binary file (zlib-compressed blocks in
//! the appended section) is turned into the equivalent ASCII text, every number written with
//! Rust's `{}` (so a non-finite value shows as `NaN` or `inf`), so that the tests read either.

use flate2::read::ZlibDecoder;
use std::io::Read;
use std::path::Path;

/// The VTU file at `path` as ASCII VTU text.
pub fn text(path: &Path) -> String {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    to_ascii(&bytes).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// `bytes` (a VTU file, ASCII or appended binary) as ASCII VTU text.
pub fn to_ascii(bytes: &[u8]) -> Result<String, String> {
    let marker = b"<AppendedData";
    let Some(at) = bytes.windows(marker.len()).position(|w| w == marker) else {
        return String::from_utf8(bytes.to_vec()).map_err(|e| e.to_string());
    };
    let head = std::str::from_utf8(&bytes[..at]).map_err(|e| e.to_string())?;
    if !head.contains("header_type=\"UInt64\"") || !head.contains("vtkZLibDataCompressor") {
        return Err("expected UInt64 headers and zlib compression".into());
    }
    let underscore = bytes[at..]
        .iter()
        .position(|&b| b == b'_')
        .ok_or("no '_' starting the appended data")?;
    let data = &bytes[at + underscore + 1..];
    let mut out = String::new();
    let mut rest = head;
    while let Some(open) = rest.find("<DataArray") {
        out.push_str(&rest[..open]);
        let after = &rest[open..];
        let close = after.find("/>").ok_or("unclosed <DataArray")?;
        let tag = &after[..close];
        let attribute = |name: &str| -> Option<&str> {
            let start = tag.find(&format!(" {name}=\""))? + name.len() + 3;
            Some(&tag[start..start + tag[start..].find('"')?])
        };
        let offset: usize = attribute("offset")
            .ok_or("an appended array without offset")?
            .parse()
            .map_err(|_| "a bad offset")?;
        let kind = attribute("type").ok_or("an array without type")?;
        let raw = decode(data, offset)?;
        let tokens: Vec<String> = match kind {
            "Float64" => raw
                .chunks(8)
                .map(|c| f64::from_le_bytes(c.try_into().unwrap()).to_string())
                .collect(),
            "Int64" => raw
                .chunks(8)
                .map(|c| i64::from_le_bytes(c.try_into().unwrap()).to_string())
                .collect(),
            "Int32" => raw
                .chunks(4)
                .map(|c| i32::from_le_bytes(c.try_into().unwrap()).to_string())
                .collect(),
            "UInt8" => raw.iter().map(|b| b.to_string()).collect(),
            other => return Err(format!("array type {other}")),
        };
        let ascii_tag = tag
            .replace(&format!(" offset=\"{offset}\""), "")
            .replace("format=\"appended\"", "format=\"ascii\"");
        out.push_str(&ascii_tag);
        out.push_str(">\n");
        out.push_str(&tokens.join(" "));
        out.push_str("\n</DataArray>");
        rest = &after[close + 2..];
    }
    out.push_str(rest);
    out.push_str("</VTKFile>\n");
    Ok(out.replace(" compressor=\"vtkZLibDataCompressor\"", ""))
}

/// The bytes of the array at `offset` of the appended `data`: the UInt64 header [blocks, block
/// size, last partial size, compressed sizes…], then the zlib blocks.
fn decode(data: &[u8], offset: usize) -> Result<Vec<u8>, String> {
    let word = |k: usize| -> Result<usize, String> {
        let i = offset + 8 * k;
        let b = data
            .get(i..i + 8)
            .ok_or("the appended data ends in a header")?;
        Ok(u64::from_le_bytes(b.try_into().unwrap()) as usize)
    };
    let blocks = word(0)?;
    let mut pos = offset + 8 * (3 + blocks);
    let mut out = Vec::new();
    for b in 0..blocks {
        let size = word(3 + b)?;
        let block = data
            .get(pos..pos + size)
            .ok_or("the appended data ends in a block")?;
        ZlibDecoder::new(block)
            .read_to_end(&mut out)
            .map_err(|e| e.to_string())?;
        pos += size;
    }
    Ok(out)
}
