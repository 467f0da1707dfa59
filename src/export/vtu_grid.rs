//! One VTK XML unstructured grid (`.vtu`) writer for every grid the program exports: the
//! points, the cells and the data arrays, written either as ASCII text or — the default — as
//! zlib-compressed binary blocks in the file's appended section (`format="appended"`,
//! `encoding="raw"`, `compressor="vtkZLibDataCompressor"`, UInt64 headers), which ParaView,
//! VTK and meshio read. The binary file is about a fifth of the ASCII one and keeps every bit
//! of the numbers.

use flate2::write::ZlibEncoder;
use flate2::Compression;
use std::fmt::Write as _;
use std::io::Write as _;

/// How the data arrays are written.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum VtuEncoding {
    /// zlib-compressed binary blocks in the appended section (the default).
    #[default]
    Binary,
    /// Text: every number written out (shortest round-trip form).
    Ascii,
}

/// The values of a data array.
#[derive(Clone, Debug)]
pub enum Values {
    /// 64-bit floats.
    F64(Vec<f64>),
    /// 64-bit integers.
    I64(Vec<i64>),
    /// 32-bit integers.
    I32(Vec<i32>),
    /// Bytes.
    U8(Vec<u8>),
}

impl Values {
    fn vtk_type(&self) -> &'static str {
        match self {
            Values::F64(_) => "Float64",
            Values::I64(_) => "Int64",
            Values::I32(_) => "Int32",
            Values::U8(_) => "UInt8",
        }
    }

    fn len(&self) -> usize {
        match self {
            Values::F64(v) => v.len(),
            Values::I64(v) => v.len(),
            Values::I32(v) => v.len(),
            Values::U8(v) => v.len(),
        }
    }

    /// Little-endian bytes.
    fn bytes(&self) -> Vec<u8> {
        match self {
            Values::F64(v) => v.iter().flat_map(|x| x.to_le_bytes()).collect(),
            Values::I64(v) => v.iter().flat_map(|x| x.to_le_bytes()).collect(),
            Values::I32(v) => v.iter().flat_map(|x| x.to_le_bytes()).collect(),
            Values::U8(v) => v.clone(),
        }
    }

    /// The values as text, `per_line` to a line.
    fn text(&self, per_line: usize, out: &mut String) {
        let per_line = per_line.max(1);
        for i in 0..self.len() {
            let _ = match self {
                Values::F64(v) => write!(out, "{}", v[i]),
                Values::I64(v) => write!(out, "{}", v[i]),
                Values::I32(v) => write!(out, "{}", v[i]),
                Values::U8(v) => write!(out, "{}", v[i]),
            };
            out.push(if (i + 1) % per_line == 0 { '\n' } else { ' ' });
        }
        if !out.ends_with('\n') {
            out.push('\n');
        }
    }
}

/// A named data array with `components` values per point or cell.
#[derive(Clone, Debug)]
pub struct DataArray {
    /// Its name (ParaView's field name).
    pub name: String,
    /// Values per point or cell.
    pub components: usize,
    /// The values, point- or cell-major.
    pub values: Values,
}

impl DataArray {
    /// An array of `components` floats per entry.
    pub fn f64(name: &str, components: usize, values: Vec<f64>) -> DataArray {
        DataArray {
            name: name.into(),
            components,
            values: Values::F64(values),
        }
    }

    /// An array of one 32-bit integer per entry.
    pub fn i32(name: &str, values: Vec<i32>) -> DataArray {
        DataArray {
            name: name.into(),
            components: 1,
            values: Values::I32(values),
        }
    }
}

/// An unstructured grid of one piece.
#[derive(Clone, Debug, Default)]
pub struct Grid {
    /// Point coordinates, x y z per point.
    pub points: Vec<f64>,
    /// The cells' point indices, one cell after another.
    pub connectivity: Vec<i64>,
    /// Where each cell ends in `connectivity`.
    pub offsets: Vec<i64>,
    /// Each cell's VTK type.
    pub types: Vec<u8>,
    /// Point data, with the names ParaView takes as the active scalars and vectors.
    pub point_data: Vec<DataArray>,
    /// The `Scalars=` / `Vectors=` attributes of `<PointData>`.
    pub point_active: String,
    /// Cell data.
    pub cell_data: Vec<DataArray>,
    /// The `Scalars=` / `Vectors=` attributes of `<CellData>`.
    pub cell_active: String,
}

impl Grid {
    /// A grid of `points` and cells (each its point indices) all of one `vtk_type`.
    pub fn new<'a>(
        points: impl IntoIterator<Item = [f64; 3]>,
        cells: impl IntoIterator<Item = &'a [usize]>,
        vtk_type: u8,
    ) -> Grid {
        let mut grid = Grid {
            points: points.into_iter().flatten().collect(),
            ..Default::default()
        };
        for c in cells {
            grid.connectivity.extend(c.iter().map(|&i| i as i64));
            grid.offsets.push(grid.connectivity.len() as i64);
            grid.types.push(vtk_type);
        }
        grid
    }

    /// The file's bytes.
    pub fn to_bytes(&self, encoding: VtuEncoding) -> Vec<u8> {
        let mut xml = String::new();
        let mut appended: Vec<u8> = Vec::new();
        let compressor = match encoding {
            VtuEncoding::Binary => " compressor=\"vtkZLibDataCompressor\"",
            VtuEncoding::Ascii => "",
        };
        let _ = writeln!(
            xml,
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" \
             byte_order=\"LittleEndian\" header_type=\"UInt64\"{compressor}>\n\
             <UnstructuredGrid>\n<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">",
            self.points.len() / 3,
            self.types.len()
        );
        let mut array = |xml: &mut String, name: Option<&str>, components: usize, v: &Values| {
            let name = name.map(|n| format!(" Name=\"{n}\"")).unwrap_or_default();
            let comps = if components > 1 {
                format!(" NumberOfComponents=\"{components}\"")
            } else {
                String::new()
            };
            match encoding {
                VtuEncoding::Ascii => {
                    let _ = writeln!(
                        xml,
                        "<DataArray type=\"{}\"{name}{comps} format=\"ascii\">",
                        v.vtk_type()
                    );
                    v.text(components, xml);
                    xml.push_str("</DataArray>\n");
                }
                VtuEncoding::Binary => {
                    let _ = writeln!(
                        xml,
                        "<DataArray type=\"{}\"{name}{comps} format=\"appended\" offset=\"{}\"/>",
                        v.vtk_type(),
                        appended.len()
                    );
                    compressed_blocks(&v.bytes(), &mut appended);
                }
            }
        };
        xml.push_str("<Points>\n");
        array(&mut xml, None, 3, &Values::F64(self.points.clone()));
        xml.push_str("</Points>\n<Cells>\n");
        array(
            &mut xml,
            Some("connectivity"),
            1,
            &Values::I64(self.connectivity.clone()),
        );
        array(
            &mut xml,
            Some("offsets"),
            1,
            &Values::I64(self.offsets.clone()),
        );
        array(&mut xml, Some("types"), 1, &Values::U8(self.types.clone()));
        xml.push_str("</Cells>\n");
        for (tag, active, arrays) in [
            ("PointData", &self.point_active, &self.point_data),
            ("CellData", &self.cell_active, &self.cell_data),
        ] {
            if arrays.is_empty() {
                continue;
            }
            let _ = writeln!(xml, "<{tag} {active}>");
            for a in arrays {
                array(&mut xml, Some(&a.name), a.components, &a.values);
            }
            let _ = writeln!(xml, "</{tag}>");
        }
        xml.push_str("</Piece>\n</UnstructuredGrid>\n");
        let mut bytes = xml.into_bytes();
        if encoding == VtuEncoding::Binary {
            bytes.extend_from_slice(b"<AppendedData encoding=\"raw\">\n_");
            bytes.extend_from_slice(&appended);
            bytes.extend_from_slice(b"\n</AppendedData>\n");
        }
        bytes.extend_from_slice(b"</VTKFile>\n");
        bytes
    }
}

/// Uncompressed bytes per zlib block (VTK's default).
const BLOCK: usize = 1 << 15;

/// Appends `data` to `out` as VTK's compressed layout: the UInt64 header [number of blocks,
/// block size, size of the last partial block (0 when it is full), compressed size of each
/// block], then the zlib streams of the blocks.
fn compressed_blocks(data: &[u8], out: &mut Vec<u8>) {
    let blocks: Vec<Vec<u8>> = data
        .chunks(BLOCK)
        .map(|chunk| {
            let mut z = ZlibEncoder::new(Vec::new(), Compression::default());
            z.write_all(chunk).expect("writing to memory");
            z.finish().expect("writing to memory")
        })
        .collect();
    let header = [
        blocks.len() as u64,
        BLOCK as u64,
        (data.len() % BLOCK) as u64,
    ]
    .into_iter()
    .chain(blocks.iter().map(|b| b.len() as u64));
    for h in header {
        out.extend_from_slice(&h.to_le_bytes());
    }
    for b in &blocks {
        out.extend_from_slice(b);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use flate2::read::ZlibDecoder;
    use std::io::Read;

    /// The arrays of a binary file decoded by the layout alone (header, blocks), in order.
    fn decoded_arrays(bytes: &[u8]) -> Vec<Vec<u8>> {
        let text = String::from_utf8_lossy(bytes);
        let start = bytes
            .windows(2)
            .position(|w| w == b"\n_")
            .expect("appended data")
            + 2;
        let offsets: Vec<usize> = text
            .split("offset=\"")
            .skip(1)
            .map(|t| t.split('"').next().unwrap().parse().unwrap())
            .collect();
        offsets
            .iter()
            .map(|&o| {
                let at = |k: usize| {
                    let i = start + o + 8 * k;
                    u64::from_le_bytes(bytes[i..i + 8].try_into().unwrap()) as usize
                };
                let blocks = at(0);
                let mut data = Vec::new();
                let mut pos = start + o + 8 * (3 + blocks);
                for b in 0..blocks {
                    let size = at(3 + b);
                    ZlibDecoder::new(&bytes[pos..pos + size])
                        .read_to_end(&mut data)
                        .unwrap();
                    pos += size;
                }
                data
            })
            .collect()
    }

    /// A grid larger than one block (so the last block is partial) written binary decodes to
    /// the same bits; written ASCII, it reads back to the same numbers.
    #[test]
    fn binary_and_ascii_hold_the_same_numbers() {
        let n = 5000;
        let points: Vec<[f64; 3]> = (0..n)
            .map(|i| {
                let t = i as f64;
                [t.sin() * 1e-3, t.cos() / 7.0, t * std::f64::consts::PI]
            })
            .collect();
        let cells: Vec<Vec<usize>> = (0..n - 3).map(|i| vec![i, i + 1, i + 2]).collect();
        let mut grid = Grid::new(points.clone(), cells.iter().map(|c| c.as_slice()), 5);
        let pressure: Vec<f64> = (0..n).map(|i| (i as f64).sqrt() * 1.1e5).collect();
        grid.point_data
            .push(DataArray::f64("p", 1, pressure.clone()));
        grid.point_active = "Scalars=\"p\"".into();
        grid.cell_data
            .push(DataArray::i32("id", (0..n as i32 - 3).collect()));
        let binary = grid.to_bytes(VtuEncoding::Binary);
        let ascii = grid.to_bytes(VtuEncoding::Ascii);
        assert!(
            binary.len() < ascii.len() / 2,
            "{} {}",
            binary.len(),
            ascii.len()
        );
        let arrays = decoded_arrays(&binary);
        assert_eq!(arrays.len(), 6);
        let f64s = |b: &[u8]| -> Vec<f64> {
            b.chunks(8)
                .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
                .collect()
        };
        assert_eq!(f64s(&arrays[0]), grid.points);
        assert_eq!(f64s(&arrays[4]), pressure);
        assert_eq!(arrays[3], vec![5u8; n - 3]);
        // The ASCII numbers: shortest round-trip text, so read back bit for bit.
        let text = String::from_utf8(ascii).unwrap();
        let p_text = text.split("Name=\"p\" format=\"ascii\">\n").nth(1).unwrap();
        let read: Vec<f64> = p_text
            .split("</DataArray>")
            .next()
            .unwrap()
            .split_whitespace()
            .map(|t| t.parse().unwrap())
            .collect();
        assert_eq!(read, pressure);
    }
}
