use super::*;
use crate::math::Pcg32;

/// A fresh, empty directory for one test.
fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("ophis-image-io-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn random_image(w: usize, h: usize, seed: u64, scale: f32) -> RgbImage {
    let mut rng = Pcg32::new(seed, 1);
    let mut img = RgbImage::new(w, h);
    for px in &mut img.data {
        *px = [0; 3].map(|_| rng.next_f32() * scale);
    }
    img
}

#[test]
fn exr_round_trip_is_exact_and_keeps_metadata() {
    let d = scratch("exr");
    let mut img = random_image(7, 5, 1, 100.0);
    img.data[3] = [-1.5, 1e-30, 65504.0 * 4.0];
    let meta = vec![
        ("comments".to_string(), "hello".to_string()),
        ("ophis.scene".to_string(), "snake.xml".to_string()),
        ("ophis.spp".to_string(), "64".to_string()),
    ];
    let p = d.join("a.exr");
    write_exr(&p, &img, &meta).unwrap();
    assert_eq!(read_image(&p).unwrap(), img);
    assert_eq!(read_exr_metadata(&p).unwrap(), meta);
    // No temporary file is left beside the result.
    assert_eq!(std::fs::read_dir(&d).unwrap().count(), 1);
    let bad = [("channels".to_string(), "x".to_string())];
    assert!(matches!(
        write_exr(&p, &img, &bad),
        Err(ImageError::Write { .. })
    ));
}

#[test]
fn exr_luminance_channel_is_read_as_gray() {
    use exr::prelude::*;
    let d = scratch("exr-y");
    let p = d.join("y.exr");
    let ys: Vec<f32> = (0..6).map(|i| i as f32 * 0.25).collect();
    let ch = AnyChannel::new("Y", FlatSamples::F32(ys.clone()));
    let image = Image::from_channels((3, 2), AnyChannels::sort(vec![ch].into()));
    image.write().to_file(&p).unwrap();
    let img = read_image(&p).unwrap();
    assert_eq!((img.width, img.height), (3, 2));
    for (px, y) in img.data.iter().zip(&ys) {
        assert_eq!(*px, [*y; 3]);
    }
}

#[test]
fn png_round_trip_within_one_code() {
    let d = scratch("png");
    let mut img = random_image(9, 4, 2, 1.2);
    img.data[0] = [f32::NAN, -1.0, 0.002];
    let p = d.join("a.png");
    write_png(&p, &img).unwrap();
    let back = read_image(&p).unwrap();
    assert_eq!((back.width, back.height), (9, 4));
    for (a, b) in img.data.iter().zip(&back.data) {
        for k in 0..3 {
            let (ea, eb) = (linear_to_srgb(a[k]), linear_to_srgb(b[k]));
            assert!((ea - eb).abs() <= 0.5 / 255.0 + 1e-5, "{a:?} {b:?}");
        }
    }
}

fn encode_png(
    path: &Path,
    w: u32,
    h: u32,
    color: png::ColorType,
    depth: png::BitDepth,
    palette: Option<Vec<u8>>,
    data: &[u8],
) {
    let f = std::fs::File::create(path).unwrap();
    let mut e = png::Encoder::new(f, w, h);
    e.set_color(color);
    e.set_depth(depth);
    if let Some(p) = palette {
        e.set_palette(p);
    }
    let mut wr = e.write_header().unwrap();
    wr.write_image_data(data).unwrap();
    wr.finish().unwrap();
}

#[test]
fn png_gray16_and_palette_are_expanded() {
    let d = scratch("png-kinds");
    let p = d.join("g16.png");
    let vals: [u16; 2] = [0, 65535 / 2];
    let data: Vec<u8> = vals.iter().flat_map(|v| v.to_be_bytes()).collect();
    encode_png(
        &p,
        2,
        1,
        png::ColorType::Grayscale,
        png::BitDepth::Sixteen,
        None,
        &data,
    );
    let img = read_image(&p).unwrap();
    assert_eq!(img.data[0], [0.0; 3]);
    let want = srgb_to_linear(32767.0 / 65535.0);
    assert!((img.data[1][0] - want).abs() < 1e-6 && img.data[1][2] == img.data[1][0]);

    let p = d.join("pal.png");
    let palette = vec![255, 0, 0, 0, 0, 255];
    // Two 1-bit indices: 1 then 0, packed into the high bits.
    encode_png(
        &p,
        2,
        1,
        png::ColorType::Indexed,
        png::BitDepth::One,
        Some(palette),
        &[0b1000_0000],
    );
    let img = read_image(&p).unwrap();
    assert_eq!(img.data, vec![[0.0, 0.0, 1.0], [1.0, 0.0, 0.0]]);
}

/// Test-side RGBE encoder: mantissas are floor(v / 2^(e−8)) for the shared exponent e of the
/// largest component, so decoding at the bucket centre errs by at most 2^(e−9).
fn rgbe(c: [f32; 3]) -> [u8; 4] {
    let m = c[0].max(c[1]).max(c[2]);
    if m < 1e-32 {
        return [0; 4];
    }
    let e = m.log2().floor() as i32 + 1; // m < 2^e
    let f = 2f32.powi(8 - e);
    [
        (c[0] * f) as u8,
        (c[1] * f) as u8,
        (c[2] * f) as u8,
        (e + 128) as u8,
    ]
}

fn encode_hdr(img: &RgbImage, rle: bool) -> Vec<u8> {
    let mut out = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\nEXPOSURE=1.0\n\n".to_vec();
    out.extend(format!("-Y {} +X {}\n", img.height, img.width).bytes());
    for row in img.data.chunks(img.width) {
        let px: Vec<[u8; 4]> = row.iter().map(|&c| rgbe(c)).collect();
        if !rle {
            // Old-style: a repeat of the previous pixel, n < 256 times, is (1, 1, 1, n).
            let mut i = 0;
            while i < px.len() {
                out.extend(px[i]);
                let mut n = 0;
                while i + 1 + n < px.len() && px[i + 1 + n] == px[i] && n < 255 {
                    n += 1;
                }
                if n > 0 {
                    out.extend([1, 1, 1, n as u8]);
                }
                i += 1 + n;
            }
            continue;
        }
        out.extend([2, 2, (img.width >> 8) as u8, img.width as u8]);
        for c in 0..4 {
            let vals: Vec<u8> = px.iter().map(|p| p[c]).collect();
            let mut i = 0;
            while i < vals.len() {
                let mut run = 1;
                while i + run < vals.len() && vals[i + run] == vals[i] && run < 127 {
                    run += 1;
                }
                if run >= 3 {
                    out.extend([128 + run as u8, vals[i]]);
                    i += run;
                } else {
                    let n = (vals.len() - i).min(2);
                    out.push(n as u8);
                    out.extend(&vals[i..i + n]);
                    i += n;
                }
            }
        }
    }
    out
}

#[test]
fn hdr_rle_and_flat_decode_within_rgbe_precision() {
    let d = scratch("hdr");
    let mut img = random_image(13, 3, 3, 50.0);
    for x in 4..10 {
        img.data[x] = [2.0, 1.0, 0.25]; // a run for the encoders to compress
    }
    img.data[20] = [0.0; 3];
    for rle in [true, false] {
        let p = d.join(format!("a{rle}.hdr"));
        std::fs::write(&p, encode_hdr(&img, rle)).unwrap();
        let back = read_image(&p).unwrap();
        assert_eq!((back.width, back.height), (13, 3));
        for (a, b) in img.data.iter().zip(&back.data) {
            let m = a[0].max(a[1]).max(a[2]);
            for k in 0..3 {
                assert!((a[k] - b[k]).abs() <= m / 256.0, "rle={rle} {a:?} {b:?}");
            }
        }
    }
}

fn expect_err(path: &Path) -> ImageError {
    match read_image(path) {
        Ok(_) => panic!("{} read without error", path.display()),
        Err(e) => {
            assert!(e.to_string().contains(&*path.to_string_lossy()), "{e}");
            e
        }
    }
}

#[test]
fn bad_files_give_typed_errors() {
    let d = scratch("errors");
    assert!(matches!(
        expect_err(&d.join("none.exr")),
        ImageError::Missing { .. }
    ));
    assert!(matches!(expect_err(&d), ImageError::IsDirectory { .. }));
    let empty = d.join("empty.png");
    std::fs::write(&empty, b"").unwrap();
    assert!(matches!(expect_err(&empty), ImageError::Empty { .. }));
    let junk = d.join("junk.exr");
    std::fs::write(&junk, b"this is not an image").unwrap();
    assert!(matches!(
        expect_err(&junk),
        ImageError::NotTheFormat {
            expected: "OpenEXR",
            ..
        }
    ));

    let img = random_image(16, 16, 4, 1.0);
    let hdr = encode_hdr(&img, true);
    let p = d.join("trunc.hdr");
    std::fs::write(&p, &hdr[..hdr.len() - 40]).unwrap();
    assert!(matches!(expect_err(&p), ImageError::Truncated { .. }));

    let huge = d.join("huge.hdr");
    let header = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 100000 +X 100000\n";
    std::fs::write(&huge, header).unwrap();
    assert!(matches!(expect_err(&huge), ImageError::TooLarge { .. }));
    let xyze = d.join("xyze.hdr");
    std::fs::write(
        &xyze,
        b"#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 1 +X 1\n\0\0\0\0",
    )
    .unwrap();
    assert!(matches!(expect_err(&xyze), ImageError::Unsupported { .. }));

    // A PNG or an EXR cut in half is truncated or malformed.
    let cut_in_half = |path: &Path| {
        let bytes = std::fs::read(path).unwrap();
        std::fs::write(path, &bytes[..bytes.len() / 2]).unwrap();
        let e = expect_err(path);
        let bad = matches!(
            e,
            ImageError::Truncated { .. } | ImageError::Malformed { .. }
        );
        assert!(bad, "{e}");
    };
    let png_path = d.join("t.png");
    write_png(&png_path, &img).unwrap();
    cut_in_half(&png_path);
    let exr_path = d.join("t.exr");
    write_exr(&exr_path, &img, &[]).unwrap();
    cut_in_half(&exr_path);

    let bad = RgbImage {
        width: 2,
        height: 2,
        data: vec![[0.0; 3]; 3],
    };
    assert!(write_png(d.join("bad.png"), &bad).is_err());
}
