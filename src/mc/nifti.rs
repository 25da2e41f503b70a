//! NIfTI-1 input (`.nii`, `.nii.gz`) through the `nifti` crate, with the limits checked before
//! the crate allocates: the header's volume must fit in the bytes actually present.

use super::grid::{Volume, VolumeError};
use nifti::{InMemNiftiObject, NiftiHeader, NiftiObject, NiftiVolume, RandomAccessNiftiVolume};
use std::io::Read;

/// Decompressed bytes read at most (4 GiB).
pub const MAX_BYTES: u64 = 1 << 32;

fn bad(why: impl Into<String>) -> VolumeError {
    VolumeError::Nifti(why.into())
}

/// Reads a single-file NIfTI-1 volume (gzip-compressed or not) as `f64` samples, `x` fastest,
/// with `scl_slope`/`scl_inter` applied. The volume must be 3-D (or 4-D and higher with every
/// extra dimension 1), at least 2 samples along each axis, and finite.
pub fn read_nifti(bytes: &[u8]) -> Result<Volume<f64>, VolumeError> {
    let data: Vec<u8> = if bytes.starts_with(&[0x1f, 0x8b]) {
        let mut out = Vec::new();
        flate2::read::GzDecoder::new(bytes)
            .take(MAX_BYTES + 1)
            .read_to_end(&mut out)
            .map_err(|e| bad(format!("gzip: {e}")))?;
        if out.len() as u64 > MAX_BYTES {
            return Err(bad(format!(
                "more than {MAX_BYTES} bytes after decompression"
            )));
        }
        out
    } else {
        bytes.to_vec()
    };
    let header = NiftiHeader::from_reader(&data[..]).map_err(|e| bad(format!("header: {e}")))?;
    if &header.magic != b"n+1\0" {
        return Err(bad("not a single-file NIfTI-1 volume (magic n+1)"));
    }
    let dim = header.dim().map_err(|e| bad(format!("header dim: {e}")))?;
    if dim.len() < 3 || dim[3..].iter().any(|&d| d != 1) {
        return Err(bad(format!(
            "a 3-D volume is needed, the header has dimensions {dim:?}"
        )));
    }
    let dims = [dim[0] as usize, dim[1] as usize, dim[2] as usize];
    let ty = header
        .data_type()
        .map_err(|e| bad(format!("datatype: {e}")))?;
    let voxels = dims[0] * dims[1] * dims[2]; // u16³ fits in usize
    let offset = header.vox_offset;
    if !(offset.is_finite() && offset >= 348.0) {
        return Err(bad(format!("vox_offset {offset} is not a valid offset")));
    }
    let need = offset as u64 + (voxels as u64) * ty.size_of() as u64;
    if need > data.len() as u64 {
        return Err(bad(format!(
            "truncated: {dims:?} samples of {ty:?} from byte {offset} need {need} bytes, the file has {}",
            data.len()
        )));
    }
    if dims.iter().any(|&d| d < 2) {
        return Err(VolumeError::TooSmall(dims));
    }
    let object =
        InMemNiftiObject::from_reader(&data[..]).map_err(|e| bad(format!("volume: {e}")))?;
    let volume = object.volume();
    let full: Vec<u16> = volume.dim().to_vec();
    let mut values = Vec::with_capacity(voxels);
    let mut coords = vec![0u16; full.len()];
    for k in 0..dims[2] {
        for j in 0..dims[1] {
            for i in 0..dims[0] {
                coords[0] = i as u16;
                coords[1] = j as u16;
                coords[2] = k as u16;
                let v = volume
                    .get_f64(&coords)
                    .map_err(|e| bad(format!("sample ({i}, {j}, {k}): {e}")))?;
                if !v.is_finite() {
                    return Err(VolumeError::NonFinite {
                        index: values.len(),
                    });
                }
                values.push(v);
            }
        }
    }
    Volume::new(dims, values)
}

/// A minimal single-file NIfTI-1 image of `f32` samples (`x` fastest), for tests and fuzz
/// seeds: the 348-byte header, an empty extension block, the data from byte 352.
pub fn nifti_f32_bytes(dims: [u16; 3], values: &[f32]) -> Vec<u8> {
    let mut h = vec![0u8; 352];
    h[0..4].copy_from_slice(&348i32.to_le_bytes());
    let dim: [i16; 8] = [
        3,
        dims[0] as i16,
        dims[1] as i16,
        dims[2] as i16,
        1,
        1,
        1,
        1,
    ];
    for (k, d) in dim.iter().enumerate() {
        h[40 + 2 * k..42 + 2 * k].copy_from_slice(&d.to_le_bytes());
    }
    h[70..72].copy_from_slice(&16i16.to_le_bytes()); // DT_FLOAT32
    h[72..74].copy_from_slice(&32i16.to_le_bytes());
    for k in 0..8 {
        h[76 + 4 * k..80 + 4 * k].copy_from_slice(&1f32.to_le_bytes());
    }
    h[108..112].copy_from_slice(&352f32.to_le_bytes());
    h[344..348].copy_from_slice(b"n+1\0");
    for v in values {
        h.extend_from_slice(&v.to_le_bytes());
    }
    h
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    #[test]
    fn reads_plain_and_gzipped_volumes() {
        let values: Vec<f32> = (0..24).map(|i| i as f32 * 0.5 - 3.0).collect();
        let bytes = nifti_f32_bytes([2, 3, 4], &values);
        let v = read_nifti(&bytes).unwrap();
        assert_eq!(v.dims, [2, 3, 4]);
        assert_eq!(
            v.values,
            values.iter().map(|&x| x as f64).collect::<Vec<_>>()
        );
        let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
        gz.write_all(&bytes).unwrap();
        let v2 = read_nifti(&gz.finish().unwrap()).unwrap();
        assert_eq!(v2, v);
        // Truncated data, a 1-sample axis, NaN, garbage: errors, never panics.
        assert!(matches!(
            read_nifti(&bytes[..bytes.len() - 4]),
            Err(VolumeError::Nifti(_))
        ));
        let thin = nifti_f32_bytes([1, 3, 4], &values[..12]);
        assert!(matches!(read_nifti(&thin), Err(VolumeError::TooSmall(_))));
        let mut nan = values.clone();
        nan[5] = f32::NAN;
        assert!(matches!(
            read_nifti(&nifti_f32_bytes([2, 3, 4], &nan)),
            Err(VolumeError::NonFinite { index: 5 })
        ));
        assert!(read_nifti(b"not a nifti file at all").is_err());
        assert!(read_nifti(&[0x1f, 0x8b, 0, 0]).is_err());
    }
}
