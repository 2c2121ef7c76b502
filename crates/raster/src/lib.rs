//! # shadelab-raster
//!
//! A multithreaded CPU tile rasterizer with a z-buffer and flat, Gouraud and Phong shading of
//! the classic local illumination model. Pure Rust; the Python bindings live in another crate.
//!
//! Conventions: right-handed world with y up; the camera looks down −z (OpenGL); image row 0
//! is the top and pixel `(x, y)` has its centre at `(x + 0.5, y + 0.5)`; counter-clockwise
//! faces are front faces; `DirectionalLight::direction` is where the light travels.
//!
//! ```
//! use std::sync::Arc;
//! use glam::{DVec3, Mat4, Vec3};
//! use shadelab_raster::*;
//!
//! let mesh = Arc::new(primitives::uv_sphere(16, 32));
//! let mut scene = Scene::new(Vec3::splat(0.2)).unwrap();
//! scene.add(mesh, Material::preset("gold").unwrap(), Mat4::IDENTITY).unwrap();
//! scene.add_light(DirectionalLight::new(Vec3::new(-1.0, -1.0, -1.0), Vec3::ONE, 1.0).unwrap());
//! let camera = Camera::look_at(DVec3::new(0.0, 0.0, 3.0), DVec3::ZERO, DVec3::Y, 45.0, 0.1, 100.0).unwrap();
//! let frame = render(&scene, &camera, &RenderOptions::new(64, 48), ColorFormat::U8, false).unwrap();
//! assert_eq!(frame.width, 64);
//! ```
#![warn(missing_docs)]

mod auto_shading;
mod camera;
mod crease;
mod effects;
mod environment;
mod error;
mod frame;
#[cfg(feature = "fuzzing")]
#[doc(hidden)]
pub mod fuzzing;
mod lighting;
mod lights;
mod material;
mod mesh;
mod mesh_edges;
mod mesh_solid;
mod mtl_maps;
mod obj;
mod options;
mod pipeline;
mod png_out;
mod pool;
pub mod primitives;
mod rays;
pub mod reflect;
mod render;
mod scene;
mod shadows;
mod tangents;
pub mod texture;
mod trig;

pub use auto_shading::{explain_shading, ShadingEstimate, DEFAULT_TOLERANCE};
pub use camera::{Camera, Intrinsics, Projection};
pub use effects::{Fog, FogMode};
pub use environment::{Environment, Layout as EnvironmentLayout, FACE_NAMES, MAX_ENVIRONMENT_SIZE};
pub use error::{RasterError, Result};
pub use frame::{ColorBuffer, ColorFormat, Frame, Outputs, RenderStats, StageTimings};
pub use lights::{
    AreaLight, AreaShape, DirectionalLight, Light, PointLight, SplitColors, SpotLight,
    MAX_AREA_SAMPLES, MIN_ATTENUATION_DENOMINATOR,
};
pub use lights::{
    ShadowFilter, ShadowSettings, Shadows, MAX_CASCADES, MAX_PCF_KERNEL, MAX_SHADOW_RESOLUTION,
};
pub use material::{ior_preset, preset_names, Material, Preset, IOR_PRESETS, PRESETS};
pub use mesh::{face_normal, generate_vertex_normals, Mesh};
pub use obj::{load_obj, load_obj_parts, parse_obj_parts, ObjPart};
pub use options::{
    EdgeMode, GouraudMethod, Interpolation, RenderOptions, ShadingMode, SpecularModel, Technique,
    DEFAULT_EDGE_ANGLE, DEFAULT_TRACE_DEPTH, MAX_EDGE_WIDTH, MAX_IMAGE_SIZE, MAX_SUPERSAMPLE,
    MAX_TRACE_DEPTH, SAMPLE_COUNTS,
};
pub use pipeline::shade::Pixel;
pub use pipeline::MAX_RADIANCE;
pub use png_out::{encode_png, PngCompression, PngSamples};
pub use pool::{default_threads, MAX_THREADS, PIN_THREADS_ENV};
#[doc(hidden)]
pub use pool::{max_in_flight, set_rendezvous, worker_cpus};
pub use render::{coverage_counts, render, render_depth_map, render_into, render_with};
pub use scene::{Object, Scene};
pub use tangents::generate_tangents;
pub use texture::{Filter, Footprint, Maps, Procedural, Texture, Wrap};
