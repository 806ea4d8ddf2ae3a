//! Canonical attribute order for OpenEXR headers.
//!
//! The `exr` crate keeps custom attributes in a `HashMap`, so two writes of the same image
//! list them in different orders and the files differ byte for byte. Sorting the attributes
//! of a single-part header by name makes the bytes a function of the image and metadata
//! alone. The header keeps its length, so the chunk offsets after it stay valid.

/// Sorts the attributes of a single-part EXR header in place by name. Leaves anything it
/// does not recognise (multi-part files, malformed headers) untouched.
pub(crate) fn sort_header_attributes(bytes: &mut [u8]) {
    const MULTIPART: u32 = 0x1000;
    if bytes.len() < 8 {
        return;
    }
    let version = u32::from_le_bytes([bytes[4], bytes[5], bytes[6], bytes[7]]);
    if version & MULTIPART != 0 {
        return;
    }
    let start = 8;
    let mut at = start;
    let mut attrs: Vec<(usize, usize)> = Vec::new();
    loop {
        match bytes.get(at) {
            None => return,
            Some(0) => break,
            Some(_) => {}
        }
        let begin = at;
        let Some(after_name) = skip_cstr(bytes, at) else {
            return;
        };
        let Some(after_type) = skip_cstr(bytes, after_name) else {
            return;
        };
        let Some(size) = bytes.get(after_type..after_type + 4) else {
            return;
        };
        let size = i32::from_le_bytes([size[0], size[1], size[2], size[3]]);
        if size < 0 {
            return;
        }
        at = after_type + 4 + size as usize;
        if at > bytes.len() {
            return;
        }
        attrs.push((begin, at));
    }
    let end = at;
    let name = |&(b, _): &(usize, usize)| {
        let e = bytes[b..].iter().position(|&c| c == 0).unwrap_or(0);
        bytes[b..b + e].to_vec()
    };
    let mut sorted = attrs.clone();
    sorted.sort_by_key(name);
    let mut out = Vec::with_capacity(end - start);
    for (b, e) in sorted {
        out.extend_from_slice(&bytes[b..e]);
    }
    bytes[start..end].copy_from_slice(&out);
}

fn skip_cstr(bytes: &[u8], at: usize) -> Option<usize> {
    let n = bytes.get(at..)?.iter().position(|&c| c == 0)?;
    Some(at + n + 1)
}
