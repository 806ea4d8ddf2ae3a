//! Accelerator benchmark (not a test): PLY load, mesh construction and BVH build times on one and
//! on all threads, tree statistics, and ray throughput of every instruction-set variant for
//! camera rays, bounce rays (closest hit) and shadow rays (any hit), with a checksum of the hits
//! (equal checksums: identical hits, bit for bit).
//!
//! ```text
//! cargo run --release --example bench_accel -- [MESH.ply] [--scene FILE.xml] [-D name=value]
//!     [--repeat 3] [--side 512]
//! ```
//!
//! Without `--scene` the shapes are the Cornell room of `scenes/cornell-mesh.xml` around
//! `MESH.ply` (default `target/bench/blob.ply`, written by `bench/make_mesh.py`), seen from the
//! benchmark camera. With `--scene` they are the scene's shapes and camera.
//!
//! Rays are traced one by one (`Accel::intersect`, `Accel::occluded`) and in batches of 1024
//! given as columns (`Bvh::intersect_raw_columns`, `Bvh::occluded_columns`), as the wavefront
//! integrator traces them (on trees of `INTERLEAVE_BLOCKS` blocks or more, the 1M-triangle mesh
//! among them, with their single-ray walks interleaved).
//!
//! Rays: camera rays through a `side`² grid; from each camera hit, a bounce ray in a cosine-
//! distributed direction (incoherent) and a shadow ray to a random point of the ceiling light
//! (for `--scene`: of the scene's bounds). Load and build times are wall-clock minima over
//! `--repeat` runs; ray times are minima of the thread's CPU time (steadier on a shared machine).

use ophis::accel::{Accel, Bvh, Isa, RayColumns};
use ophis::math::{warp, Frame, Pcg32, Ray, Transform, Vec2, Vec3};
use ophis::scene::build::{load_scene, LoadOptions};
use ophis::shape::{Hit, MeshOptions, Shape, TriangleMesh};
use std::path::PathBuf;
use std::time::Instant;

fn peak_rss_mb() -> f64 {
    let s = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    s.lines()
        .find(|l| l.starts_with("VmHWM:"))
        .and_then(|l| l.split_whitespace().nth(1))
        .and_then(|k| k.parse::<f64>().ok())
        .map_or(f64::NAN, |k| k / 1024.0)
}

/// CPU seconds of the calling thread (wall-clock seconds where that cannot be read). On a busy
/// machine this is much steadier than wall time, since time spent descheduled does not count.
fn thread_seconds() -> f64 {
    let t = ophis::render::cpu_seconds(ophis::render::CpuClock::Thread);
    if t.is_finite() {
        return t;
    }
    thread_local!(static START: Instant = Instant::now());
    START.with(|s| s.elapsed().as_secs_f64())
}

fn best<T>(repeat: usize, mut f: impl FnMut() -> T) -> (f64, T) {
    let mut out = None;
    let mut best = f64::INFINITY;
    for _ in 0..repeat.max(1) {
        let t = Instant::now();
        let v = f();
        best = best.min(t.elapsed().as_secs_f64());
        out = Some(v);
    }
    (best, out.unwrap())
}

/// Minimum CPU time of this thread over `repeat` runs of `f`, and its last result.
fn best_cpu<T>(repeat: usize, mut f: impl FnMut() -> T) -> (f64, T) {
    let mut out = None;
    let mut best = f64::INFINITY;
    for _ in 0..repeat.max(1) {
        let t = thread_seconds();
        let v = f();
        best = best.min(thread_seconds() - t);
        out = Some(v);
    }
    (best, out.unwrap())
}

/// The Cornell room of scenes/cornell-mesh.xml: five walls and the light as rectangles.
fn room() -> Vec<Shape> {
    let r = |t: Transform| Shape::Mesh(TriangleMesh::rectangle(&t, false).unwrap());
    let rot = |axis: Vec3, deg: f32| Transform::rotate(axis, deg).unwrap();
    vec![
        r(Transform::translate(Vec3::new(0.0, -1.0, 0.0)).compose(&rot(Vec3::X, -90.0))),
        r(Transform::translate(Vec3::new(0.0, 1.0, 0.0)).compose(&rot(Vec3::X, 90.0))),
        r(Transform::translate(Vec3::new(0.0, 0.0, -1.0))),
        r(Transform::translate(Vec3::new(-1.0, 0.0, 0.0)).compose(&rot(Vec3::Y, 90.0))),
        r(Transform::translate(Vec3::new(1.0, 0.0, 0.0)).compose(&rot(Vec3::Y, -90.0))),
        r(Transform::translate(Vec3::new(0.0, 0.99, 0.0))
            .compose(&rot(Vec3::X, 90.0))
            .compose(&Transform::scale(Vec3::new(0.25, 0.25, 1.0)).unwrap())),
    ]
}

fn hash_hit(h: &Option<Hit>) -> u64 {
    match h {
        Some(h) => {
            (h.t.to_bits() as u64)
                ^ ((h.prim as u64) << 20)
                ^ ((h.shape as u64) << 50)
                ^ (h.uv.x.to_bits() as u64).rotate_left(7)
                ^ (h.uv.y.to_bits() as u64).rotate_left(37)
        }
        None => 0x9e37_79b9,
    }
}

/// Traces `rays` one by one; returns a checksum of the results. Not inlined, so that a profile
/// (callgrind) shows the tracing cost as this function's inclusive cost.
#[inline(never)]
fn trace_rays(bvh: &Bvh, shapes: &[Shape], rays: &[Ray], any: bool) -> u64 {
    let mut sum = 0u64;
    for r in rays {
        let v = if any {
            bvh.occluded(shapes, r) as u64
        } else {
            hash_hit(&bvh.intersect(shapes, r))
        };
        sum = sum.wrapping_mul(3).wrapping_add(v);
    }
    sum
}

/// [`trace_rays`] in batches of 1024 rays, as the wavefront integrator traces them: as
/// columns (`Bvh::intersect_raw_columns`, `Bvh::occluded_columns`); the same checksum.
fn trace_batches(bvh: &Bvh, shapes: &[Shape], rays: &[Ray], any: bool) -> u64 {
    let mut sum = 0u64;
    let mut hits = vec![None; 1024];
    let mut blocked = vec![false; 1024];
    let mut cols = [(); 7].map(|_| vec![0.0f32; 1024]);
    for chunk in rays.chunks(1024) {
        let n = chunk.len();
        for (i, r) in chunk.iter().enumerate() {
            let v = [r.o.x, r.o.y, r.o.z, r.d.x, r.d.y, r.d.z, r.t_max];
            for (c, x) in cols.iter_mut().zip(v) {
                c[i] = x;
            }
        }
        let columns = RayColumns {
            o: [&cols[0][..n], &cols[1][..n], &cols[2][..n]],
            d: [&cols[3][..n], &cols[4][..n], &cols[5][..n]],
            t_max: &cols[6][..n],
            n,
        };
        if any {
            bvh.occluded_columns(shapes, &columns, &mut blocked[..n]);
            for &b in &blocked[..n] {
                sum = sum.wrapping_mul(3).wrapping_add(b as u64);
            }
        } else {
            bvh.intersect_raw_columns(shapes, &columns, &mut hits[..n]);
            for h in &hits[..n] {
                sum = sum
                    .wrapping_mul(3)
                    .wrapping_add(hash_hit(&h.map(|h| h.hit)));
            }
        }
    }
    sum
}

struct Args {
    mesh: PathBuf,
    scene: Option<PathBuf>,
    defines: Vec<(String, String)>,
    repeat: usize,
    side: usize,
}

fn args() -> Args {
    let mut a = Args {
        mesh: PathBuf::from("target/bench/blob.ply"),
        scene: None,
        defines: Vec::new(),
        repeat: 3,
        side: 512,
    };
    let mut it = std::env::args().skip(1);
    while let Some(s) = it.next() {
        match s.as_str() {
            "--repeat" => a.repeat = it.next().and_then(|s| s.parse().ok()).unwrap_or(3),
            "--side" => a.side = it.next().and_then(|s| s.parse().ok()).unwrap_or(512),
            "--scene" => a.scene = it.next().map(PathBuf::from),
            "-D" => {
                let kv = it.next().unwrap_or_default();
                if let Some((k, v)) = kv.split_once('=') {
                    a.defines.push((k.into(), v.into()));
                }
            }
            _ => a.mesh = PathBuf::from(s),
        }
    }
    a
}

fn main() {
    let a = args();
    let threads = rayon::current_num_threads();
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let (shapes, camera): (Vec<Shape>, Box<dyn Fn(Vec2) -> Ray>) = match &a.scene {
        Some(path) => {
            let opts = LoadOptions {
                defines: a.defines.clone(),
                ..Default::default()
            };
            let (scene, _) = load_scene(path, &opts).expect("scene loads");
            println!("{}: {} primitives", path.display(), scene.primitive_count());
            let cam = scene.camera.clone();
            (
                scene.shapes,
                Box::new(move |u| cam.generate_ray(u, Vec2::splat(0.5))),
            )
        }
        None => {
            let (t_read, data) = best(a.repeat, || ophis::shape::ply::read_ply(&a.mesh).unwrap());
            let (t_mesh, mesh) = best(a.repeat, || {
                TriangleMesh::from_data(
                    data.clone(),
                    &a.mesh,
                    &Transform::IDENTITY,
                    &MeshOptions::default(),
                )
                .unwrap()
            });
            println!(
                "{}: {} triangles; PLY read {:.1} ms, mesh {:.1} ms",
                a.mesh.display(),
                mesh.triangle_count(),
                t_read * 1e3,
                t_mesh * 1e3
            );
            drop(data);
            let mut shapes = room();
            shapes.push(Shape::Mesh(mesh));
            let tan = (39.3f32.to_radians() * 0.5).tan();
            let cam = move |u: Vec2| {
                let d = Vec3::new((2.0 * u.x - 1.0) * tan, (1.0 - 2.0 * u.y) * tan, -1.0);
                Ray::new(Vec3::new(0.0, 0.0, 3.9), d.normalize())
            };
            (shapes, Box::new(cam))
        }
    };
    let (t_build1, _) = best(a.repeat, || one.install(|| Bvh::build(&shapes)));
    let (t_build, mut bvh) = best(a.repeat, || Bvh::build(&shapes));
    println!(
        "BVH build {:.1} ms on 1 thread, {:.1} ms on {threads} ({:.2}x); {} nodes, {} blocks \
         ({:.0} % of slots used), depth {}, {:.1} MB ({:.1} bytes per primitive)",
        t_build1 * 1e3,
        t_build * 1e3,
        t_build1 / t_build,
        bvh.node_count(),
        bvh.block_count(),
        100.0 * bvh.prim_count() as f64 / (4 * bvh.block_count()).max(1) as f64,
        bvh.depth(),
        bvh.memory_bytes() as f64 / 1e6,
        bvh.memory_bytes() as f64 / bvh.prim_count().max(1) as f64
    );

    let side = a.side;
    let mut cam = Vec::with_capacity(side * side);
    for j in 0..side {
        for i in 0..side {
            let u = Vec2::new(
                (i as f32 + 0.5) / side as f32,
                (j as f32 + 0.5) / side as f32,
            );
            cam.push(camera(u));
        }
    }
    let b = bvh.bounds();
    let mut rng = Pcg32::new(7, 1);
    let mut bounce = Vec::new();
    let mut shadow = Vec::new();
    for r in &cam {
        let Some(h) = bvh.intersect(&shapes, r) else {
            continue;
        };
        let si = shapes[h.shape as usize].interaction(&h, r);
        let ng = if si.ng.dot(r.d) > 0.0 { -si.ng } else { si.ng };
        let d = Frame::from_z(ng).to_world(warp::square_to_cosine_hemisphere(rng.next_vec2()));
        bounce.push(Ray::spawn(si.p, ng, d));
        let u = rng.next_vec2();
        let target = if a.scene.is_some() {
            b.min + (b.max - b.min) * Vec3::new(u.x, rng.next_f32(), u.y)
        } else {
            Vec3::new(0.5 * u.x - 0.25, 0.99, 0.5 * u.y - 0.25)
        };
        shadow.push(Ray::spawn_to(si.p, ng, target));
    }
    println!("rays, Mrays/s of one thread's CPU time (checksum):");
    let supported: Vec<Isa> = Isa::ALL.into_iter().filter(|i| i.supported()).collect();
    for (name, rays, any) in [
        ("camera", &cam, false),
        ("bounce", &bounce, false),
        ("shadow", &shadow, true),
    ] {
        for (mode, trace) in [
            (
                "one by one",
                trace_rays as fn(&Bvh, &[Shape], &[Ray], bool) -> u64,
            ),
            ("in batches", trace_batches),
        ] {
            let mut line = format!("  {name:<7} {:>8} {mode}", rays.len());
            for &isa in &supported {
                bvh.set_isa(isa);
                let (t, sum) = best_cpu(a.repeat, || trace(&bvh, &shapes, rays, any));
                line += &format!(
                    "  {}: {:6.2} ({:04x})",
                    isa.name(),
                    rays.len() as f64 / t / 1e6,
                    sum & 0xffff
                );
            }
            println!("{line}");
        }
    }
    println!("peak RSS {:.1} MB", peak_rss_mb());
}
