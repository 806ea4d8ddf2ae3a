//! Compares ophis's RGBE reader (`src/image_io/hdr.rs`, called through
//! `ophis::image_io::decode_image`) with the `image`
//! crate's (`hdr` feature only) and `radiant`: speed on a large run-length encoded file, the
//! values each decodes, and the errors each gives for broken files. A measurement, not a test:
//!
//!     cd bench/hdr_decoders && cargo run --release
//!
//! (its own package, outside ophis's dependencies; the results are in hdr.rs's header.)
use std::io::Cursor;
use std::path::Path;
use std::time::Instant;

use ophis::image_io::{decode_image, MAX_PIXELS};

fn ophis(data: &[u8]) -> Result<Vec<[f32; 3]>, String> {
    decode_image(Path::new("sky.hdr"), data)
        .map(|i| i.data)
        .map_err(|e| e.to_string())
}
fn image_crate(data: &[u8]) -> Result<Vec<[f32; 3]>, String> {
    use image::ImageDecoder;
    let d = image::codecs::hdr::HdrDecoder::new(Cursor::new(data)).map_err(|e| e.to_string())?;
    let (w, h) = d.dimensions();
    // As ophis would: refuse an image beyond its size limit before allocating.
    if (w as usize)
        .checked_mul(h as usize)
        .is_none_or(|n| n > MAX_PIXELS)
    {
        return Err(format!("(caller's check) {w} × {h} too large"));
    }
    let mut buf = vec![0u8; d.total_bytes() as usize];
    d.read_image(&mut buf).map_err(|e| e.to_string())?;
    let f: &[f32] = bytemuck_cast(&buf);
    assert_eq!(f.len(), (w * h * 3) as usize);
    Ok(f.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect())
}
fn bytemuck_cast(b: &[u8]) -> &[f32] {
    assert!(b.as_ptr() as usize % 4 == 0 && b.len() % 4 == 0);
    unsafe { std::slice::from_raw_parts(b.as_ptr() as *const f32, b.len() / 4) }
}
fn radiant_crate(data: &[u8]) -> Result<Vec<[f32; 3]>, String> {
    let img = radiant::load(Cursor::new(data)).map_err(|e| format!("{e:?} / {e}"))?;
    Ok(img.data.iter().map(|p| [p.r, p.g, p.b]).collect())
}

/// A smooth sky-like RGBE file, new-style run-length encoded (as Radiance writes), w × h.
fn make_hdr(w: usize, h: usize) -> Vec<u8> {
    let mut out = format!("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {h} +X {w}\n").into_bytes();
    for y in 0..h {
        let mut scan = vec![[0u8; 4]; w];
        for (x, p) in scan.iter_mut().enumerate() {
            let u = x as f32 / w as f32;
            let v = y as f32 / h as f32;
            // A bright "sun" and a gradient sky, quantised like a real capture.
            let sun = if (u - 0.3).abs() < 0.01 && (v - 0.2).abs() < 0.01 {
                5e4
            } else {
                0.0
            };
            let rgb = [
                0.2 + 0.8 * (1.0 - v) + sun,
                0.3 + 0.5 * (1.0 - v) + sun,
                0.6 + 0.4 * u + sun,
            ];
            let m = rgb.iter().cloned().fold(0.0f32, f32::max);
            let e = m.log2().floor() as i32 + 1;
            let f = 2f32.powi(8 - e);
            *p = [
                (rgb[0] * f) as u8,
                (rgb[1] * f) as u8,
                (rgb[2] * f) as u8,
                (e + 128) as u8,
            ];
            // Noise in the low bit so that runs are short, as in photographs.
            p[0] ^= ((x * 7 + y * 13) % 3 == 0) as u8;
        }
        out.extend_from_slice(&[2, 2, (w >> 8) as u8, (w & 255) as u8]);
        for c in 0..4 {
            let mut x = 0;
            while x < w {
                let mut run = 1;
                while x + run < w && run < 127 && scan[x + run][c] == scan[x][c] {
                    run += 1;
                }
                if run >= 4 {
                    out.push(128 + run as u8);
                    out.push(scan[x][c]);
                    x += run;
                } else {
                    let mut n = 0;
                    while x + n < w && n < 128 {
                        let mut r = 1;
                        while x + n + r < w && r < 4 && scan[x + n + r][c] == scan[x + n][c] {
                            r += 1;
                        }
                        if r >= 4 {
                            break;
                        }
                        n += 1;
                    }
                    out.push(n as u8);
                    out.extend(scan[x..x + n].iter().map(|p| p[c]));
                    x += n;
                }
            }
        }
    }
    out
}

fn time(name: &str, data: &[u8], f: fn(&[u8]) -> Result<Vec<[f32; 3]>, String>) -> Vec<[f32; 3]> {
    let mut best = f64::MAX;
    let mut out = Vec::new();
    for _ in 0..7 {
        let t = Instant::now();
        out = f(data).unwrap();
        best = best.min(t.elapsed().as_secs_f64());
    }
    let mpix = out.len() as f64 / 1e6;
    println!(
        "{name:8} best of 7: {:7.1} ms  ({:.0} Mpixel/s)",
        best * 1e3,
        mpix / best
    );
    out
}

fn main() {
    let only = std::env::args().nth(1);
    let (w, h) = (8192, 4096);
    let data = make_hdr(w, h);
    println!("{w} × {h} RLE RGBE, {:.1} MB", data.len() as f64 / 1e6);
    if only.as_deref() == Some("radiant-huge") {
        let _ = radiant_crate(b"#?RADIANCE\n\n-Y 100000 +X 100000\n\x02\x02");
        return;
    }
    if only.is_some() {
        return main_cases(only);
    }
    let a = time("ophis", &data, ophis);
    let b = time("image", &data, image_crate);
    let c = time("radiant", &data, radiant_crate);
    for (name, other) in [("image", &b), ("radiant", &c)] {
        let worst = a
            .iter()
            .zip(other.iter())
            .flat_map(|(p, q)| (0..3).map(move |i| ((p[i] - q[i]) / p[i].max(1e-30)).abs()))
            .fold(0.0f32, f32::max);
        println!("largest relative difference ophis vs {name}: {worst:.3e}");
    }
    main_cases(None);
}

fn main_cases(only: Option<String>) {
    let small = make_hdr(64, 8);
    let header_end = small.windows(2).position(|w| w == b"\n\n").unwrap() + 2;
    let res_end = header_end
        + small[header_end..]
            .iter()
            .position(|&b| b == b'\n')
            .unwrap()
        + 1;
    let mut bad_rle = small.clone();
    bad_rle[res_end + 4] = 200; // a run of 72 in a 64-pixel scanline
    let cases: Vec<(&str, Vec<u8>)> = vec![
        ("truncated pixels", small[..small.len() - 50].to_vec()),
        ("no signature", small[2..].to_vec()),
        (
            "header not ended",
            b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n".to_vec(),
        ),
        (
            "XYZE",
            String::from_utf8_lossy(&small)
                .replace("32-bit_rle_rgbe", "32-bit_rle_xyze")
                .into_bytes(),
        ),
        (
            "bad resolution",
            String::from_utf8_lossy(&small[..res_end])
                .replace("-Y 8", "-Y x8")
                .into_bytes()
                .into_iter()
                .chain(small[res_end..].iter().cloned())
                .collect(),
        ),
        (
            "huge resolution",
            b"#?RADIANCE\n\n-Y 100000 +X 100000\n\x02\x02".to_vec(),
        ),
        ("run overflows", bad_rle),
    ];
    for (what, d) in cases {
        if only.as_deref().is_some_and(|o| o != what) {
            continue;
        }
        println!("--- {what}");
        println!("  ophis:   {:?}", ophis(&d).err());
        println!("  image:   {:?}", image_crate(&d).err());
        if what == "huge resolution" && only.is_none() {
            // It may abort the process (allocation failure), so it runs in a child.
            let st = std::process::Command::new(std::env::current_exe().unwrap())
                .arg("radiant-huge")
                .output()
                .unwrap();
            let err = String::from_utf8_lossy(&st.stderr);
            println!(
                "  radiant: child exited {:?}: {}",
                st.status.code(),
                err.lines().next().unwrap_or("")
            );
            continue;
        }
        println!("  radiant: {:?}", radiant_crate(&d).err());
    }
}
