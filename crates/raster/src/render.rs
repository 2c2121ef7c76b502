//! The public entry points: `render`, `render_into` and the coverage test hook.

use crate::auto_shading;
use crate::camera::Camera;
use crate::error::{RasterError, Result};
use crate::frame::{ColorBuffer, ColorFormat, Frame, Outputs, RenderStats};
use crate::options::RenderOptions;
use crate::pipeline;
use crate::pipeline::shade::{Out, Pixel};
use crate::pipeline::Buffers;
use crate::pool;
use crate::scene::Scene;

/// An empty vector with room for exactly `len` values, or [`RasterError::OutOfMemory`].
fn reserve<T>(len: usize) -> Result<Vec<T>> {
    let mut v = Vec::new();
    v.try_reserve_exact(len)
        .map_err(|_| RasterError::OutOfMemory {
            bytes: len.saturating_mul(std::mem::size_of::<T>()),
        })?;
    Ok(v)
}

/// Renders `scene` seen by `camera` into newly allocated buffers: the colour, and the
/// depth when `with_depth`.
pub fn render(
    scene: &Scene,
    camera: &Camera,
    options: &RenderOptions,
    format: ColorFormat,
    with_depth: bool,
) -> Result<Frame> {
    let outputs = Outputs {
        depth: with_depth,
        coverage: false,
    };
    render_with(scene, camera, options, format, outputs)
}

/// [`render`] with the chosen [`Outputs`] besides the colour.
pub fn render_with(
    scene: &Scene,
    camera: &Camera,
    options: &RenderOptions,
    format: ColorFormat,
    outputs: Outputs,
) -> Result<Frame> {
    options.validate()?;
    let n = options.pixel_count();
    let mut depth = if outputs.depth {
        Some(reserve::<f32>(n)?)
    } else {
        None
    };
    let mut coverage = if outputs.coverage {
        Some(reserve::<f32>(n)?)
    } else {
        None
    };
    // The buffers are not zeroed: the pipeline writes every sample (at 1080p on two cores
    // the time outside the pipeline's stages fell from 0.43 to about 0.2 ms per frame).
    fn fill<P: Pixel>(
        scene: &Scene,
        camera: &Camera,
        options: &RenderOptions,
        n: usize,
        depth: &mut Option<Vec<f32>>,
        coverage: &mut Option<Vec<f32>>,
    ) -> Result<(Vec<P>, RenderStats)> {
        let mut c = reserve::<P>(n * 3)?;
        let out = Buffers {
            color: &mut c.spare_capacity_mut()[..n * 3],
            depth: depth.as_mut().map(|d| &mut d.spare_capacity_mut()[..n]),
            coverage: coverage.as_mut().map(|v| &mut v.spare_capacity_mut()[..n]),
        };
        let stats = run_checked(scene, camera, options, out)?;
        // SAFETY: the pipeline succeeded, so it wrote all `n·3` colour samples and, when
        // asked for, all `n` depths and coverages (`color_pass`'s contract); each vector
        // has that capacity.
        unsafe {
            c.set_len(n * 3);
            for v in [depth, coverage].into_iter().flatten() {
                v.set_len(n);
            }
        }
        Ok((c, stats))
    }
    let (color, stats) = match format {
        ColorFormat::U8 => {
            let (c, s) = fill::<u8>(scene, camera, options, n, &mut depth, &mut coverage)?;
            (ColorBuffer::U8(c), s)
        }
        ColorFormat::F32 => {
            let (c, s) = fill::<f32>(scene, camera, options, n, &mut depth, &mut coverage)?;
            (ColorBuffer::F32(c), s)
        }
    };
    Ok(Frame {
        width: options.width,
        height: options.height,
        color,
        depth,
        coverage,
        stats,
    })
}

/// Renders into caller-provided row-major buffers: `color` holds `height·width·3` samples
/// (`u8` or `f32`), `depth` (optional) `height·width` eye-space depths.
pub fn render_into<P: Pixel>(
    scene: &Scene,
    camera: &Camera,
    options: &RenderOptions,
    color: &mut [P],
    depth: Option<&mut [f32]>,
) -> Result<RenderStats> {
    // SAFETY: `MaybeUninit<T>` has `T`'s layout, and the pipeline only ever writes
    // initialised values through these views, so the caller's slices stay initialised.
    let color = unsafe { &mut *(color as *mut [P] as *mut [Out<P>]) };
    // SAFETY: as for `color`.
    let depth = depth.map(|d| unsafe { &mut *(d as *mut [f32] as *mut [Out<f32>]) });
    let out = Buffers {
        color,
        depth,
        coverage: None,
    };
    run_checked(scene, camera, options, out)
}

/// Checks the options and buffer sizes, then runs the pipeline on the thread pool.
fn run_checked<P: Pixel>(
    scene: &Scene,
    camera: &Camera,
    options: &RenderOptions,
    out: Buffers<'_, P>,
) -> Result<RenderStats> {
    options.validate()?;
    let n = options.pixel_count();
    if out.color.len() != n * 3 {
        return Err(RasterError::invalid(format!(
            "colour buffer has {} samples, expected {}x{}x3 = {}",
            out.color.len(),
            options.height,
            options.width,
            n * 3
        )));
    }
    for (name, buf) in [("depth", &out.depth), ("coverage", &out.coverage)] {
        if let Some(b) = buf.as_ref().filter(|b| b.len() != n) {
            return Err(RasterError::invalid(format!(
                "{name} buffer has {} samples, expected {n}",
                b.len()
            )));
        }
    }
    pool::run(options.threads, || {
        // `shading="auto"`: the modes are chosen here, inside the render's time.
        let auto = options.tolerance.map(|t| {
            auto_shading::plan(
                scene,
                options,
                auto_shading::estimate(scene, camera, options, t),
            )
        });
        let (options, modes, estimates) = match &auto {
            Some((estimates, opts, modes)) => (opts, modes.as_deref(), estimates.clone()),
            None => (options, None, Vec::new()),
        };
        let mut stats = if options.supersample > 1 {
            supersampled(scene, camera, options, modes, out)
        } else {
            pipeline::color_pass(scene, camera, options, modes, out)
        }?;
        stats.shading = estimates;
        Ok(stats)
    })?
}

/// `supersample = k`: renders `k·width × k·height` linear float pixels and averages each
/// k×k block into one output pixel (a box filter; the mean in f32, summed in row order, then
/// stored as the output type). The depth output is the nearest eye depth of the block
/// (+inf where no triangle is).
fn supersampled<P: Pixel>(
    scene: &Scene,
    camera: &Camera,
    options: &RenderOptions,
    modes: Option<&[crate::options::ShadingMode]>,
    out: Buffers<'_, P>,
) -> Result<RenderStats> {
    let Buffers {
        color,
        depth,
        coverage,
    } = out;
    use rayon::prelude::*;
    let k = options.supersample as usize;
    let w = options.width as usize;
    let mut big = options.clone();
    big.width *= options.supersample;
    big.height *= options.supersample;
    big.supersample = 1;
    // Lines keep their width in output pixels.
    big.edge_width *= options.supersample as f32;
    let n = big.pixel_count();
    let mut c = reserve::<f32>(n * 3)?;
    let mut d = match depth {
        Some(_) => Some(reserve::<f32>(n)?),
        None => None,
    };
    let mut v = match coverage {
        Some(_) => Some(reserve::<f32>(n)?),
        None => None,
    };
    let big_out = Buffers {
        color: &mut c.spare_capacity_mut()[..n * 3],
        depth: d.as_mut().map(|d| &mut d.spare_capacity_mut()[..n]),
        coverage: v.as_mut().map(|v| &mut v.spare_capacity_mut()[..n]),
    };
    let stats = pipeline::color_pass(scene, camera, &big, modes, big_out)?;
    // SAFETY: the pass succeeded, so it wrote all `n·3` colour samples and, when asked for,
    // all `n` depths and coverages; each vector has that capacity.
    unsafe {
        c.set_len(n * 3);
        for b in [d.as_mut(), v.as_mut()].into_iter().flatten() {
            b.set_len(n);
        }
    }
    let (bw, kk) = (w * k, (k * k) as f32);
    color
        .par_chunks_mut(w * 3)
        .enumerate()
        .for_each(|(y, row)| {
            for (x, px) in row.chunks_exact_mut(3).enumerate() {
                let mut sum = [0.0f32; 3];
                for sy in 0..k {
                    let base = ((y * k + sy) * bw + x * k) * 3;
                    for s in c[base..base + k * 3].chunks_exact(3) {
                        for (a, v) in sum.iter_mut().zip(s) {
                            *a += v;
                        }
                    }
                }
                let mut out = [P::default(); 3];
                P::store(&mut out, glam::Vec3::from_array(sum) / kk);
                for (o, v) in px.iter_mut().zip(out) {
                    o.write(v);
                }
            }
        });
    if let (Some(out), Some(v)) = (coverage, v.as_ref()) {
        // The mean coverage of the block, summed in row order.
        out.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
            for (x, o) in row.iter_mut().enumerate() {
                let mut sum = 0.0f32;
                for sy in 0..k {
                    let base = (y * k + sy) * bw + x * k;
                    sum += v[base..base + k].iter().sum::<f32>();
                }
                o.write(sum / kk);
            }
        });
    }
    if let (Some(out), Some(d)) = (depth, d.as_ref()) {
        out.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
            for (x, o) in row.iter_mut().enumerate() {
                let mut near = f32::INFINITY;
                for sy in 0..k {
                    let base = (y * k + sy) * bw + x * k;
                    for &v in &d[base..base + k] {
                        near = near.min(v);
                    }
                }
                o.write(near);
            }
        });
    }
    Ok(stats)
}

/// The window depth of every pixel, row-major `height·width`, from the visibility pass alone
/// (nothing is shaded; no material or light is read): reversed-Z, 1 at the near plane and 0
/// at the far plane, −1 where no triangle is. This is the pass a shadow map renders from a
/// light; [`render`]'s depth output is the eye-space distance of the same visibility.
pub fn render_depth_map(
    scene: &Scene,
    camera: &Camera,
    options: &RenderOptions,
) -> Result<(Vec<f32>, RenderStats)> {
    options.validate()?;
    let n = options.pixel_count();
    let mut depth = reserve::<f32>(n)?;
    let stats = pool::run(options.threads, || {
        pipeline::depth_pass(
            scene,
            camera,
            options,
            &mut depth.spare_capacity_mut()[..n],
            false,
        )
    })??;
    // SAFETY: the pass succeeded, so it wrote all `n` depths (every tile writes every pixel
    // of its rows); the vector has that capacity.
    unsafe { depth.set_len(n) };
    Ok((depth, stats))
}

/// Test hook: per-pixel count of covering triangles (no depth test), row-major
/// `height·width`, of the triangles setup keeps (`options.cull_hidden` drops a solid's
/// hidden back faces: a closed mesh then counts 1 inside instead of 2). Watertight meshes
/// give exactly 1 inside and 0 outside.
#[doc(hidden)]
pub fn coverage_counts(
    scene: &Scene,
    camera: &Camera,
    options: &RenderOptions,
) -> Result<Vec<u32>> {
    options.validate()?;
    pool::run(options.threads, || {
        pipeline::coverage_counts(scene, camera, options)
    })?
}
