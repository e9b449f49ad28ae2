//! `EXT_meshopt_compression` and `KHR_meshopt_compression`: buffer views stored compressed (as
//! gltfpack and other web pipelines write them), decoded here as the extensions' Appendix A
//! (bitstreams) and B (filters) specify: attributes (mode 0: byte-wise deltas in blocks of
//! groups of 16; version 1, the Khronos extension's, with control modes per byte and channel
//! modes per 4 bytes), triangles (mode 1: edge and vertex FIFOs), indices (mode 2: two delta
//! baselines), and the octahedral, quaternion, exponential and (Khronos) colour filters. Every
//! read is bounds-checked: a truncated or corrupt stream is an error, never a panic.

use serde::Deserialize;

/// The most bytes any mode decodes from one compressed byte.
const MAX_EXPANSION: usize = 64;

/// A compressed view's extension object.
#[derive(Debug, Deserialize)]
#[serde(rename_all = "camelCase")]
pub(super) struct Compressed {
    pub buffer: usize,
    #[serde(default)]
    pub byte_offset: u64,
    pub byte_length: u64,
    pub byte_stride: usize,
    pub count: usize,
    pub mode: String,
    #[serde(default)]
    pub filter: Option<String>,
}

/// The bytes `data` (the compressed range) decode to under `c`'s mode and filter:
/// `count × byteStride` bytes.
pub(super) fn decode(c: &Compressed, data: &[u8]) -> Result<Vec<u8>, String> {
    let (count, stride) = (c.count, c.byte_stride);
    // No bitstream packs more than 64 bytes into one (attributes whose groups are all
    // unchanged take 2 bits a byte of 16 elements): a larger claim is refused before anything
    // is allocated for it.
    let claimed = count.checked_mul(stride);
    if claimed.is_none_or(|n| n > MAX_EXPANSION * data.len() + ATTRIBUTE_TAIL) {
        return Err(format!(
            "{count} elements of {stride} bytes claimed from {} compressed bytes",
            data.len()
        ));
    }
    let filter = c.filter.as_deref().unwrap_or("NONE");
    match c.mode.as_str() {
        "ATTRIBUTES" => {
            if stride == 0 || !stride.is_multiple_of(4) || stride > 256 {
                return Err(format!(
                    "byteStride {stride} is not a multiple of 4 up to 256"
                ));
            }
            let mut bytes = decode_attributes(count, stride, data)?;
            apply_filter(filter, stride, &mut bytes)?;
            Ok(bytes)
        }
        "TRIANGLES" | "INDICES" if filter != "NONE" => {
            Err(format!("filter {filter} is for ATTRIBUTES only"))
        }
        "TRIANGLES" => {
            let indices = decode_triangles(count, data)?;
            write_indices(&indices, stride)
        }
        "INDICES" => {
            let indices = decode_index_sequence(count, data)?;
            write_indices(&indices, stride)
        }
        mode => Err(format!("unknown mode {mode:?}")),
    }
}

/// Indices as little-endian integers of `size` bytes (2 or 4).
fn write_indices(indices: &[u32], size: usize) -> Result<Vec<u8>, String> {
    match size {
        2 => Ok(indices
            .iter()
            .flat_map(|&i| (i as u16).to_le_bytes())
            .collect()),
        4 => Ok(indices.iter().flat_map(|&i| i.to_le_bytes()).collect()),
        _ => Err(format!("index byteStride {size} is neither 2 nor 4")),
    }
}

/// A cursor over a stream, every read checked.
struct Reader<'a> {
    data: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize) -> Result<&'a [u8], String> {
        let end = self.at.checked_add(n).filter(|&end| end <= self.data.len());
        let end = end.ok_or("the stream ends early")?;
        let bytes = &self.data[self.at..end];
        self.at = end;
        Ok(bytes)
    }

    fn byte(&mut self) -> Result<u8, String> {
        Ok(self.take(1)?[0])
    }

    /// An unsigned LEB128 ("varint-7") value of up to 32 bits.
    fn varint(&mut self) -> Result<u32, String> {
        let mut value = 0u32;
        for shift in (0..35).step_by(7) {
            let byte = self.byte()?;
            value |= u32::from(byte & 0x7f) << shift;
            if byte & 0x80 == 0 {
                return Ok(value);
            }
        }
        Err("a varint longer than 5 bytes".into())
    }
}

/// The header byte of `data`, checked, and the rest.
fn after_header(data: &[u8], expected: u8, what: &str) -> Result<(), String> {
    match data.first() {
        Some(&header) if header == expected => Ok(()),
        Some(&header) => Err(format!(
            "{what} header 0x{header:02x}, expected 0x{expected:02x}"
        )),
        None => Err("an empty stream".into()),
    }
}

/// The smallest tail of a version 0 attribute stream: the baseline element, padded to 32 bytes.
const ATTRIBUTE_TAIL: usize = 32;
/// The same for version 1 (`KHR_meshopt_compression`), whose tail also holds the channel modes.
const ATTRIBUTE_TAIL_V1: usize = 24;

/// How one group of 16 byte deltas is stored.
#[derive(Clone, Copy)]
enum GroupEncoding {
    /// All zero, nothing stored.
    Zero,
    /// Codes of this many bits (1, 2 or 4), the all-ones code a sentinel for a byte after them.
    Bits(usize),
    /// 16 bytes.
    Raw,
}

use GroupEncoding::{Bits, Raw, Zero};

/// The encodings a group's 2 header bits pick: version 0's, and version 1's under control
/// modes 0 and 1.
const ENCODINGS_V0: [GroupEncoding; 4] = [Zero, Bits(2), Bits(4), Raw];
const ENCODINGS_V1: [[GroupEncoding; 4]; 2] = [
    [Zero, Bits(1), Bits(2), Bits(4)],
    [Bits(1), Bits(2), Bits(4), Raw],
];

/// Mode 0: `count` elements of `stride` bytes, in version 0 (`EXT_meshopt_compression`) or
/// version 1 (`KHR_meshopt_compression`: a control mode per byte position and block, and a
/// channel mode per 4 bytes, which adds 16-bit deltas and rotated 32-bit xor deltas).
fn decode_attributes(count: usize, stride: usize, data: &[u8]) -> Result<Vec<u8>, String> {
    let version = match data.first() {
        Some(0xa0) => 0,
        Some(0xa1) => 1,
        Some(&header) => {
            return Err(format!(
                "attribute header 0x{header:02x}, expected 0xa0 or 0xa1"
            ));
        }
        None => return Err("an empty stream".into()),
    };
    let channel_count = if version == 1 { stride / 4 } else { 0 };
    let tail = (stride + channel_count).max(if version == 1 {
        ATTRIBUTE_TAIL_V1
    } else {
        ATTRIBUTE_TAIL
    });
    if data.len() < 1 + tail {
        return Err("the stream is shorter than its tail".into());
    }
    let modes_start = data.len() - channel_count;
    let mut last = data[modes_start - stride..modes_start].to_vec();
    let channel_modes: Vec<u8> = match version {
        1 => data[modes_start..].to_vec(),
        _ => vec![0; stride / 4],
    };
    for &mode in &channel_modes {
        if (mode & 15) > 2 || ((mode & 15) < 2 && mode >> 4 != 0) {
            return Err(format!("channel mode 0x{mode:02x}"));
        }
    }
    let mut reader = Reader {
        data: &data[..data.len() - tail],
        at: 1,
    };
    let max_block = ((8192 / stride) & !15).min(256);
    let mut out = vec![0u8; count * stride];
    let mut deltas = vec![0u8; stride * 256];
    let mut done = 0;
    while done < count {
        let block = (count - done).min(max_block);
        let groups = block.div_ceil(16);
        let control = match version {
            1 => reader.take(stride / 4)?,
            _ => &[][..],
        };
        for k in 0..stride {
            let byte_deltas = &mut deltas[k * 256..k * 256 + groups * 16];
            let encodings = match version {
                1 => match (control[k / 4] >> ((k % 4) * 2)) & 3 {
                    2 => {
                        byte_deltas.fill(0);
                        continue;
                    }
                    3 => {
                        // Literal: one delta byte an element, no header.
                        byte_deltas[..block].copy_from_slice(reader.take(block)?);
                        continue;
                    }
                    c => ENCODINGS_V1[usize::from(c)],
                },
                _ => ENCODINGS_V0,
            };
            let header = reader.take(groups.div_ceil(4))?;
            for group in 0..groups {
                let bits = (header[group / 4] >> ((group % 4) * 2)) & 3;
                let slot = &mut byte_deltas[group * 16..group * 16 + 16];
                read_group(&mut reader, encodings[usize::from(bits)], slot)?;
            }
        }
        for (channel, &mode) in channel_modes.iter().enumerate() {
            let delta = |k: usize, i: usize| deltas[(4 * channel + k) * 256 + i];
            let element = |i: usize| (done + i) * stride + 4 * channel;
            let previous = &mut last[4 * channel..4 * channel + 4];
            match mode & 15 {
                0 => {
                    for (k, previous) in previous.iter_mut().enumerate() {
                        for i in 0..block {
                            *previous = previous.wrapping_add(unzigzag8(delta(k, i)));
                            out[element(i) + k] = *previous;
                        }
                    }
                }
                1 => {
                    for half in 0..2 {
                        let mut value =
                            u16::from_le_bytes([previous[2 * half], previous[2 * half + 1]]);
                        for i in 0..block {
                            let d =
                                u16::from_le_bytes([delta(2 * half, i), delta(2 * half + 1, i)]);
                            value = value.wrapping_add(unzigzag16(d));
                            out[element(i) + 2 * half..element(i) + 2 * half + 2]
                                .copy_from_slice(&value.to_le_bytes());
                        }
                        previous[2 * half..2 * half + 2].copy_from_slice(&value.to_le_bytes());
                    }
                }
                _ => {
                    let rotation = u32::from(mode >> 4);
                    let mut value =
                        u32::from_le_bytes([previous[0], previous[1], previous[2], previous[3]]);
                    for i in 0..block {
                        let d = u32::from_le_bytes([
                            delta(0, i),
                            delta(1, i),
                            delta(2, i),
                            delta(3, i),
                        ]);
                        value ^= d.rotate_right(rotation);
                        out[element(i)..element(i) + 4].copy_from_slice(&value.to_le_bytes());
                    }
                    previous.copy_from_slice(&value.to_le_bytes());
                }
            }
        }
        done += block;
    }
    if reader.at != reader.data.len() {
        return Err("bytes left over before the tail".into());
    }
    Ok(out)
}

/// One group's 16 zigzagged deltas as `encoding` stores them.
fn read_group(
    reader: &mut Reader,
    encoding: GroupEncoding,
    deltas: &mut [u8],
) -> Result<(), String> {
    let width = match encoding {
        Zero => {
            deltas.fill(0);
            return Ok(());
        }
        Raw => {
            deltas.copy_from_slice(reader.take(16)?);
            return Ok(());
        }
        Bits(width) => width,
    };
    let packed = reader.take(16 * width / 8)?;
    let sentinel = (1u8 << width) - 1;
    let per_byte = 8 / width;
    for (i, delta) in deltas.iter_mut().enumerate() {
        // 1-bit codes run from the least significant bit, wider ones from the most.
        let shift = if width == 1 {
            i % 8
        } else {
            8 - width * (i % per_byte + 1)
        };
        let code = (packed[i / per_byte] >> shift) & sentinel;
        *delta = if code == sentinel {
            reader.byte()?
        } else {
            code
        };
    }
    Ok(())
}

fn unzigzag16(v: u16) -> u16 {
    if v & 1 != 0 { !(v >> 1) } else { v >> 1 }
}

fn unzigzag8(v: u8) -> u8 {
    if v & 1 != 0 { !(v >> 1) } else { v >> 1 }
}

/// A 16-entry FIFO, entry 0 the most recently pushed.
struct Fifo<T: Copy + Default> {
    entries: [T; 16],
    next: usize,
}

impl<T: Copy + Default> Fifo<T> {
    fn new() -> Self {
        Fifo {
            entries: [T::default(); 16],
            next: 0,
        }
    }

    fn push(&mut self, value: T) {
        self.entries[self.next] = value;
        self.next = (self.next + 1) & 15;
    }

    fn get(&self, age: usize) -> T {
        self.entries[(self.next + 15 - (age & 15)) & 15]
    }
}

/// The triangle tail: the 16-byte `codeaux` table.
const TRIANGLE_TAIL: usize = 16;

/// Mode 1: `count` indices (a multiple of 3) of a triangle list.
fn decode_triangles(count: usize, data: &[u8]) -> Result<Vec<u32>, String> {
    after_header(data, 0xe1, "triangle")?;
    if !count.is_multiple_of(3) {
        return Err(format!("{count} triangle indices are not a multiple of 3"));
    }
    let triangles = count / 3;
    if data.len() < 1 + triangles + TRIANGLE_TAIL {
        return Err("the stream is shorter than its codes and tail".into());
    }
    let codes = &data[1..1 + triangles];
    let codeaux = &data[data.len() - TRIANGLE_TAIL..];
    let mut extra = Reader {
        data: &data[..data.len() - TRIANGLE_TAIL],
        at: 1 + triangles,
    };
    let (mut next, mut last) = (0u32, 0u32);
    let decode_index = |extra: &mut Reader, last: &mut u32| -> Result<u32, String> {
        *last = last.wrapping_add(unzigzag32(extra.varint()?));
        Ok(*last)
    };
    let mut edges: Fifo<(u32, u32)> = Fifo::new();
    let mut vertices: Fifo<u32> = Fifo::new();
    let mut out = Vec::with_capacity(count);
    for &code in codes {
        let (high, low) = (usize::from(code >> 4), code & 15);
        let (a, b, c) = if high < 15 {
            let (a, b) = edges.get(high);
            let c = match low {
                0 => {
                    next += 1;
                    next - 1
                }
                1..=12 => vertices.get(usize::from(low)),
                13 | 14 => {
                    last = if low == 13 {
                        last.wrapping_sub(1)
                    } else {
                        last.wrapping_add(1)
                    };
                    last
                }
                _ => decode_index(&mut extra, &mut last)?,
            };
            if !(1..=12).contains(&low) {
                vertices.push(c);
            }
            edges.push((c, b));
            edges.push((a, c));
            (a, b, c)
        } else {
            let (z, w, explicit_a) = if low < 14 {
                let aux = codeaux[usize::from(low)];
                (aux >> 4, aux & 15, false)
            } else {
                let zw = extra.byte()?;
                if zw == 0 {
                    next = 0;
                }
                (zw >> 4, zw & 15, low == 15)
            };
            let a = if explicit_a {
                decode_index(&mut extra, &mut last)?
            } else {
                next += 1;
                next - 1
            };
            let mut other = |nibble: u8| -> Result<u32, String> {
                Ok(match nibble {
                    0 => {
                        next += 1;
                        next - 1
                    }
                    15 => decode_index(&mut extra, &mut last)?,
                    n => vertices.get(usize::from(n) - 1),
                })
            };
            let b = other(z)?;
            let c = other(w)?;
            vertices.push(a);
            if z == 0 || z == 15 {
                vertices.push(b);
            }
            if w == 0 || w == 15 {
                vertices.push(c);
            }
            edges.push((b, a));
            edges.push((c, b));
            edges.push((a, c));
            (a, b, c)
        };
        out.extend([a, b, c]);
    }
    if extra.at != extra.data.len() {
        return Err("extra bytes after the last triangle's data".into());
    }
    Ok(out)
}

fn unzigzag32(v: u32) -> u32 {
    if v & 1 != 0 { !(v >> 1) } else { v >> 1 }
}

/// Mode 2: `count` indices, each a delta from one of two baselines.
fn decode_index_sequence(count: usize, data: &[u8]) -> Result<Vec<u32>, String> {
    after_header(data, 0xd1, "index")?;
    let tail = 4;
    if data.len() < 1 + tail {
        return Err("the stream is shorter than its tail".into());
    }
    let mut reader = Reader {
        data: &data[..data.len() - tail],
        at: 1,
    };
    let mut last = [0u32; 2];
    (0..count)
        .map(|_| {
            let v = reader.varint()?;
            let baseline = (v & 1) as usize;
            let delta = if v & 2 != 0 { !(v >> 2) } else { v >> 2 };
            last[baseline] = last[baseline].wrapping_add(delta);
            Ok(last[baseline])
        })
        .collect()
}

/// Appendix B's filters on decoded attributes, in place.
fn apply_filter(filter: &str, stride: usize, bytes: &mut [u8]) -> Result<(), String> {
    match (filter, stride) {
        ("NONE", _) => {}
        ("OCTAHEDRAL", 4) => bytes.chunks_exact_mut(4).for_each(octahedral8),
        ("OCTAHEDRAL", 8) => bytes.chunks_exact_mut(8).for_each(octahedral16),
        ("QUATERNION", 8) => bytes.chunks_exact_mut(8).for_each(quaternion),
        ("EXPONENTIAL", _) => bytes.chunks_exact_mut(4).for_each(exponential),
        ("COLOR", 4) => bytes.chunks_exact_mut(4).for_each(color8),
        ("COLOR", 8) => bytes.chunks_exact_mut(8).for_each(color16),
        (filter @ ("OCTAHEDRAL" | "QUATERNION" | "COLOR"), stride) => {
            return Err(format!("filter {filter} does not take byteStride {stride}"));
        }
        (filter, _) => return Err(format!("unknown filter {filter:?}")),
    }
    Ok(())
}

/// The octahedral filter's unit vector from components `x`, `y` and `one`, each scaled to
/// `max` and rounded.
fn octahedral(x: f32, y: f32, one: f32, max: f32) -> [f32; 3] {
    let (mut x, mut y) = (x / one, y / one);
    let z = 1.0 - x.abs() - y.abs();
    let t = z.min(0.0);
    x -= t.copysign(x);
    y -= t.copysign(y);
    let length = (x * x + y * y + z * z).sqrt();
    [x, y, z].map(|c| (c / length * max).round())
}

fn octahedral8(e: &mut [u8]) {
    let [x, y, one] = [0, 1, 2].map(|i| f32::from(e[i] as i8));
    let out = octahedral(x, y, one, 127.0);
    for (byte, value) in e.iter_mut().zip(out) {
        *byte = (value as i8) as u8;
    }
}

fn octahedral16(e: &mut [u8]) {
    let component = |i: usize| f32::from(i16::from_le_bytes([e[2 * i], e[2 * i + 1]]));
    let out = octahedral(component(0), component(1), component(2), 32767.0);
    for (i, value) in out.into_iter().enumerate() {
        e[2 * i..2 * i + 2].copy_from_slice(&(value as i16).to_le_bytes());
    }
}

fn quaternion(e: &mut [u8]) {
    let input: [i16; 4] = std::array::from_fn(|i| i16::from_le_bytes([e[2 * i], e[2 * i + 1]]));
    let range = std::f32::consts::FRAC_1_SQRT_2;
    let one = f32::from(input[3] | 3);
    let [x, y, z] = [0, 1, 2].map(|i| f32::from(input[i]) / one * range);
    let w = (1.0 - x * x - y * y - z * z).max(0.0).sqrt();
    let largest = (input[3] & 3) as usize;
    let mut out = [0i16; 4];
    for (offset, value) in [w, x, y, z].into_iter().enumerate() {
        out[(largest + offset) % 4] = (value * 32767.0).round() as i16;
    }
    for (i, value) in out.into_iter().enumerate() {
        e[2 * i..2 * i + 2].copy_from_slice(&value.to_le_bytes());
    }
}

/// The colour filter (`KHR_meshopt_compression`): YCoCg of K bits, K from the alpha's top bit,
/// to RGBA normalized to `max` (255 or 65535). Components as integers: Y and alpha unsigned,
/// Co and Cg signed.
fn ycocg(y: i32, co: i32, cg: i32, alpha: u32, max: f32) -> [f32; 4] {
    let top = 31 - alpha.max(1).leading_zeros();
    let scale_bits = (1u32 << (top + 1)) - 1;
    let a = alpha & (scale_bits >> 1);
    let a = (a << 1) | (a & 1);
    let scale = max / scale_bits as f32;
    [y + co - cg, y + cg, y - co - cg, a as i32].map(|c| (c as f32 * scale).round())
}

fn color8(e: &mut [u8]) {
    let out = ycocg(
        i32::from(e[0]),
        i32::from(e[1] as i8),
        i32::from(e[2] as i8),
        u32::from(e[3]),
        255.0,
    );
    for (byte, value) in e.iter_mut().zip(out) {
        *byte = value.clamp(0.0, 255.0) as u8;
    }
}

fn color16(e: &mut [u8]) {
    let word = |i: usize| u16::from_le_bytes([e[2 * i], e[2 * i + 1]]);
    let out = ycocg(
        i32::from(word(0)),
        i32::from(word(1) as i16),
        i32::from(word(2) as i16),
        u32::from(word(3)),
        65535.0,
    );
    for (i, value) in out.into_iter().enumerate() {
        let value = value.clamp(0.0, 65535.0) as u16;
        e[2 * i..2 * i + 2].copy_from_slice(&value.to_le_bytes());
    }
}

fn exponential(e: &mut [u8]) {
    let input = i32::from_le_bytes([e[0], e[1], e[2], e[3]]);
    let exponent = input >> 24;
    let mantissa = (input << 8) >> 8;
    let value = 2f32.powi(exponent) * mantissa as f32;
    e.copy_from_slice(&value.to_le_bytes());
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The reference decoder's test streams (meshoptimizer's `js/meshopt_decoder.test.js`):
    /// the streams and what they decode to are data, checked here byte for byte.
    fn attributes(count: usize, stride: usize, filter: &str, data: &[u8]) -> Vec<u8> {
        let c = Compressed {
            buffer: 0,
            byte_offset: 0,
            byte_length: data.len() as u64,
            byte_stride: stride,
            count,
            mode: "ATTRIBUTES".into(),
            filter: Some(filter.into()),
        };
        decode(&c, data).expect("decodes")
    }

    fn u16s(bytes: &[u8]) -> Vec<u16> {
        bytes
            .chunks_exact(2)
            .map(|c| u16::from_le_bytes([c[0], c[1]]))
            .collect()
    }

    #[test]
    fn attribute_streams_decode_as_the_reference_does() {
        let mut encoded = vec![
            0xa0, 0x01, 0x3f, 0x00, 0x00, 0x00, 0x58, 0x57, 0x58, 0x01, 0x26, 0x00, 0x00, 0x00,
            0x01, 0x0c, 0x00, 0x00, 0x00, 0x58, 0x01, 0x08, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
            0x00, 0x01, 0x3f, 0x00, 0x00, 0x00, 0x17, 0x18, 0x17, 0x01, 0x26, 0x00, 0x00, 0x00,
            0x01, 0x0c, 0x00, 0x00, 0x00, 0x17, 0x01, 0x08, 0x00,
        ];
        encoded.resize(85, 0);
        let expected = [
            0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 44, 1, 0, 0, 0, 0, 0, 0, 244, 1, 0, 0, 0, 0, 44, 1,
            0, 0, 0, 0, 0, 0, 244, 1, 44, 1, 44, 1, 0, 0, 0, 0, 244, 1, 244, 1,
        ];
        assert_eq!(attributes(4, 12, "NONE", &encoded), expected);

        let mut more = vec![
            0xa0, 0x00, 0x01, 0x2a, 0xaa, 0xaa, 0xaa, 0x02, 0x04, 0x44, 0x44, 0x44, 0x44, 0x44,
            0x44, 0x44, 0x03, 0x00, 0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x10,
            0x10, 0x10, 0x10, 0x10, 0x10,
        ];
        more.resize(more.len() + 32, 0);
        let expected: Vec<u8> = (0..16u8).flat_map(|i| [0, i, 2 * i, 8 * i]).collect();
        assert_eq!(attributes(16, 4, "NONE", &more), expected);

        let mut mode2 = vec![0xa0];
        for byte in [0x08u8, 0x0a, 0x0c, 0x0e] {
            mode2.extend([0x02, byte]);
            mode2.extend([byte * 0x11; 7]);
        }
        mode2.resize(mode2.len() + 32, 0);
        let expected: Vec<u8> = (0..16u8)
            .flat_map(|i| [4 * i, 5 * i, 6 * i, 7 * i])
            .collect();
        assert_eq!(attributes(16, 4, "NONE", &mode2), expected);
    }

    #[test]
    fn filtered_streams_decode_as_the_reference_does() {
        let mut oct8 = vec![
            0xa0, 0x01, 0x07, 0x00, 0x00, 0x00, 0x1e, 0x01, 0x3f, 0x00, 0x00, 0x00, 0x8b, 0x8c,
            0xfd, 0x00, 0x01, 0x26, 0x00, 0x00, 0x00,
        ];
        oct8.resize(oct8.len() + 29, 0);
        oct8.extend([0x01, 0x7f, 0x00]);
        let expected = [0, 1, 127, 0, 0, 159, 82, 1, 255, 1, 127, 0, 1, 130, 241, 1];
        assert_eq!(attributes(4, 4, "OCTAHEDRAL", &oct8), expected);

        let body = [
            0xa0, 0x01, 0x0f, 0x00, 0x00, 0x00, 0x3d, 0x5a, 0x01, 0x0f, 0x00, 0x00, 0x00, 0x0e,
            0x0d, 0x01, 0x3f, 0x00, 0x00, 0x00, 0x9a, 0x99, 0x26, 0x01, 0x3f, 0x00, 0x00, 0x00,
            0x0e, 0x0d, 0x0a, 0x00, 0x00,
        ];
        // The two 12-bit streams share all but their seventh data block's codes and their
        // baseline element (the stream's last bytes).
        let stream12 = |codes: u8, baseline: [u8; 6]| {
            let mut stream = body.to_vec();
            stream.extend([0x01, codes]);
            stream.resize(65, 0);
            stream.extend(baseline);
            stream
        };
        let oct12 = stream12(0x26, [0x01, 0x00, 0xff, 0x07, 0x00, 0x00]);
        let expected = [
            0, 16, 32767, 0, 0, 32621, 3088, 1, 32764, 16, 471, 0, 307, 28541, 16093, 1,
        ];
        assert_eq!(u16s(&attributes(4, 8, "OCTAHEDRAL", &oct12)), expected);

        let quat12 = stream12(0x2a, [0x01, 0x00, 0x00, 0x00, 0xfc, 0x07]);
        let expected = [
            32767, 0, 11, 0, 0, 25013, 0, 21166, 11, 0, 23504, 22830, 158, 14715, 0, 29277,
        ];
        assert_eq!(u16s(&attributes(4, 8, "QUATERNION", &quat12)), expected);

        let mut exp = vec![0xa0];
        exp.resize(37, 0);
        exp.extend([
            0x03, 0x00, 0x00, 0xff, 0xf7, 0xff, 0xff, 0x02, 0xff, 0xff, 0x7f, 0xfe,
        ]);
        let decoded = attributes(1, 16, "EXPONENTIAL", &exp);
        let words: Vec<u32> = decoded
            .chunks_exact(4)
            .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
        assert_eq!(words, [0, 0x3fc00000, 0xc2100000, 0x49fffffe]);
    }

    #[test]
    fn version_1_streams_and_the_colour_filter_decode_as_the_reference_does() {
        // Three channels: rotated xor deltas (mode 0x62), byte deltas, rotated xor deltas.
        let mut v1 = vec![
            0xa1, 0xee, 0xaa, 0xee, 0x00, 0x4b, 0x4b, 0x4b, 0x00, 0x00, 0x4b, 0x00, 0x00, 0x7d,
            0x7d, 0x7d, 0x00, 0x00, 0x7d, 0x00,
        ];
        v1.resize(41, 0);
        v1.extend([0x62, 0x00, 0x62]);
        let expected = [
            0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 44, 1, 0, 0, 0, 0, 0, 0, 244, 1, 0, 0, 0, 0, 44, 1,
            0, 0, 0, 0, 0, 0, 244, 1, 44, 1, 44, 1, 0, 0, 0, 0, 244, 1, 244, 1,
        ];
        assert_eq!(attributes(4, 12, "NONE", &v1), expected);

        let mut color8 = vec![0xa0];
        for sentinels in [
            [0x7e, 0x7d, 0x4c],
            [0xfd, 0xfd, 0xfe],
            [0x83, 0x82, 0x80],
            [0x7d, 0x3f, 0x7e],
        ] {
            color8.extend([0x01, 0x3f, 0x00, 0x00, 0x00]);
            color8.extend(sentinels);
        }
        color8.resize(61, 0);
        color8.extend([0x40, 0x7f, 0xc1, 0xff]);
        let expected = [
            254, 1, 0, 255, 0, 254, 0, 128, 1, 0, 255, 64, 102, 102, 102, 191,
        ];
        assert_eq!(attributes(4, 4, "COLOR", &color8), expected);
    }

    #[test]
    fn index_streams_decode_as_the_reference_does() {
        let aux = [
            0x00, 0x76, 0x87, 0x56, 0x67, 0x78, 0xa9, 0x86, 0x65, 0x89, 0x68, 0x98, 0x01, 0x69,
            0x00, 0x00,
        ];
        let mut v1 = vec![0xe1, 0xf0, 0x10, 0xfe, 0x1f, 0x3d, 0x00, 0x0a];
        v1.extend(aux);
        let expected = [0, 1, 2, 2, 1, 3, 0, 1, 2, 2, 1, 5, 2, 1, 4];
        assert_eq!(decode_triangles(15, &v1).expect("decodes"), expected);

        let mut more = vec![
            0xe1, 0xf0, 0x10, 0xfe, 0xff, 0xf0, 0x0c, 0xff, 0x02, 0x02, 0x02,
        ];
        more.extend(aux);
        let expected = [0, 1, 2, 2, 1, 3, 4, 6, 5, 7, 8, 9];
        assert_eq!(decode_triangles(12, &more).expect("decodes"), expected);

        let mut edges = vec![0xe1, 0xf0, 0x20, 0x30, 0x40];
        edges.extend(aux);
        let expected = [0, 1, 2, 1, 0, 3, 2, 1, 4, 0, 2, 5];
        assert_eq!(decode_triangles(12, &edges).expect("decodes"), expected);

        let sequence = [
            0xd1, 0x00, 0x04, 0xcd, 0x01, 0x04, 0x07, 0x98, 0x1f, 0x00, 0x00, 0x00, 0x00,
        ];
        let expected = [0, 1, 51, 2, 49, 1000];
        assert_eq!(
            decode_index_sequence(6, &sequence).expect("decodes"),
            expected
        );
    }

    /// A truncated or mislabelled stream is an error, whatever its mode.
    #[test]
    fn corrupt_streams_are_errors_not_panics() {
        let mut more = vec![
            0xa0, 0x00, 0x01, 0x2a, 0xaa, 0xaa, 0xaa, 0x02, 0x04, 0x44, 0x44, 0x44, 0x44, 0x44,
        ];
        more.resize(more.len() + 32, 0);
        let c = Compressed {
            buffer: 0,
            byte_offset: 0,
            byte_length: more.len() as u64,
            byte_stride: 4,
            count: 16,
            mode: "ATTRIBUTES".into(),
            filter: None,
        };
        for cut in 0..more.len() {
            let _ = decode(&c, &more[..cut]);
        }
        assert!(decode(&c, &more[..20]).is_err());
        assert!(decode_triangles(12, &[0xe0, 0xf0]).is_err());
        assert!(decode_triangles(3, &[0xe1, 0xff, 0xff]).is_err());
        assert!(decode_index_sequence(3, &[0xd1, 0x80, 0, 0, 0, 0]).is_err());
        for cut in 0..8 {
            let _ = decode_triangles(6, &[0xe1, 0xff, 0xf0, 0xff, 0x81, 0x80, 0x80, 0x80][..cut]);
        }
    }
}
