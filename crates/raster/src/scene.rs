//! A scene: objects (mesh + material + transform), lights and the global ambient.

use std::sync::Arc;

use glam::{DMat3, Mat3, Mat4, Vec3};

use crate::effects::Fog;
use crate::environment::Environment;
use crate::error::{RasterError, Result};
use crate::lights::Light;
use crate::material::Material;
use crate::mesh::Mesh;
use crate::texture::Maps;

/// A mesh placed in the world with a material.
#[derive(Debug, Clone)]
pub struct Object {
    mesh: Arc<Mesh>,
    material: Material,
    back_material: Option<Material>,
    /// Texture maps of both sides' materials (`None`: untextured).
    maps: Option<Arc<Maps>>,
    transform: Mat4,
    normal_matrix: Mat3,
}

impl Object {
    /// Places `mesh` with the model matrix `transform` (column vectors, `p_world = T·p`).
    ///
    /// Errors when the matrix is non-finite, singular, or not affine (last row ≠ 0 0 0 1):
    /// normals go through the inverse transpose, which needs an invertible matrix.
    pub fn new(mesh: Arc<Mesh>, material: Material, transform: Mat4) -> Result<Self> {
        if !transform.is_finite() {
            return Err(RasterError::invalid_field(
                "transform",
                "transform must be finite",
            ));
        }
        let t = transform.as_dmat4();
        if t.row(3) != glam::DVec4::new(0.0, 0.0, 0.0, 1.0) {
            return Err(RasterError::invalid_field(
                "transform",
                format!(
                    "transform must be affine (last row 0 0 0 1), got last row {:?}",
                    t.row(3).to_array()
                ),
            ));
        }
        let linear = DMat3::from_mat4(t);
        let det = linear.determinant();
        let scale = linear.x_axis.length() * linear.y_axis.length() * linear.z_axis.length();
        if det.abs() <= 1e-12 * scale || !det.is_finite() || scale == 0.0 {
            return Err(RasterError::invalid_field(
                "transform",
                "transform is singular (its 3x3 part has no inverse), so normals are undefined",
            ));
        }
        let normal_matrix = linear.inverse().transpose().as_mat3();
        Ok(Object {
            mesh,
            material,
            back_material: None,
            maps: None,
            transform,
            normal_matrix,
        })
    }

    /// The mesh.
    pub fn mesh(&self) -> &Arc<Mesh> {
        &self.mesh
    }

    /// The material.
    pub fn material(&self) -> &Material {
        &self.material
    }

    /// The same object with its own material for back faces (OpenGL's `GL_BACK` material),
    /// used only with two-sided lighting, as in OpenGL; `None` lights both sides with
    /// [`Object::material`].
    pub fn with_back_material(self, back_material: Option<Material>) -> Self {
        Object {
            back_material,
            ..self
        }
    }

    /// The same object with texture maps weighing its material per point (both sides);
    /// `None` or empty maps: untextured. A map needs the mesh's UVs; a procedural or image
    /// texture is read at each shaded point's perspective-correct (u, v).
    pub fn with_maps(self, maps: Option<Arc<Maps>>) -> Result<Self> {
        let maps = maps.filter(|m| !m.is_empty());
        if let Some(m) = &maps {
            m.check_scales()?;
        }
        if maps.as_ref().is_some_and(|m| m.perturbs()) && self.mesh.uvs().is_none() {
            let field = if maps.as_ref().is_some_and(|m| m.normal.is_some()) {
                "normal_map"
            } else {
                "bump_map"
            };
            return Err(RasterError::invalid_field(
                field,
                format!(
                    "the material has a {} but the mesh has no UVs (texture coordinates): \
                     the tangent frame comes from the UVs",
                    field.replace('_', " ")
                ),
            ));
        }
        if maps.is_some() && self.mesh.uvs().is_none() {
            return Err(RasterError::invalid_field(
                "uvs",
                "the material has texture maps but the mesh has no UVs (texture coordinates)",
            ));
        }
        Ok(Object { maps, ..self })
    }

    /// The texture maps, if any.
    pub fn maps(&self) -> Option<&Arc<Maps>> {
        self.maps.as_ref()
    }

    /// Whether the object needs the textured shading path: maps or vertex colours.
    pub fn is_textured(&self) -> bool {
        self.maps.is_some() || self.mesh.colors().is_some()
    }

    /// The back-face material, if one was set.
    pub fn back_material(&self) -> Option<&Material> {
        self.back_material.as_ref()
    }

    /// The material that lights faces of side `back` (clockwise on screen) under the scene's
    /// two-sided setting: the back material only when both are on.
    pub fn material_for(&self, back: bool, two_sided: bool) -> &Material {
        match (&self.back_material, back && two_sided) {
            (Some(m), true) => m,
            _ => &self.material,
        }
    }

    /// Replaces the (front) material.
    pub fn set_material(&mut self, material: Material) {
        self.material = material;
    }

    /// The model matrix.
    pub fn transform(&self) -> Mat4 {
        self.transform
    }

    /// Inverse transpose of the transform's 3x3 part (normals are renormalised after it).
    pub fn normal_matrix(&self) -> Mat3 {
        self.normal_matrix
    }
}

/// Everything that is drawn, and the light it is drawn in.
#[derive(Debug, Clone, Default)]
pub struct Scene {
    /// Global ambient light `Ia` (RGB).
    ambient: Vec3,
    objects: Vec<Object>,
    lights: Vec<Light>,
    fog: Option<Fog>,
    environment: Option<Environment>,
    two_sided: bool,
    infinite_viewer: bool,
}

impl Scene {
    /// An empty scene with global ambient `ambient` (finite, ≥ 0).
    pub fn new(ambient: Vec3) -> Result<Self> {
        if !ambient.is_finite() || ambient.min_element() < 0.0 {
            return Err(RasterError::invalid_field(
                "ambient",
                format!(
                    "scene ambient must be finite and >= 0, got {:?}",
                    ambient.to_array()
                ),
            ));
        }
        Ok(Scene {
            ambient,
            objects: Vec::new(),
            lights: Vec::new(),
            fog: None,
            environment: None,
            two_sided: false,
            infinite_viewer: false,
        })
    }

    /// Adds an object; see [`Object::new`].
    pub fn add(&mut self, mesh: Arc<Mesh>, material: Material, transform: Mat4) -> Result<()> {
        self.objects.push(Object::new(mesh, material, transform)?);
        Ok(())
    }

    /// Adds a placed object (e.g. one with a back material).
    pub fn add_object(&mut self, object: Object) {
        self.objects.push(object);
    }

    /// Adds every part of an OBJ file as its own object, all placed by `transform`: each
    /// keeps its MTL material (one part per `o`/`g` group and per `usemtl` switch within
    /// it), unless `material` overrides them all; parts without one get
    /// [`Material::default`]. Returns how many objects were added.
    pub fn add_obj_parts(
        &mut self,
        parts: Vec<crate::obj::ObjPart>,
        material: Option<Material>,
        back_material: Option<Material>,
        transform: Mat4,
    ) -> Result<usize> {
        let n = parts.len();
        let mut objects = Vec::with_capacity(n);
        for part in parts {
            // An overriding material replaces the MTL's maps too.
            let maps = if material.is_none() { part.maps } else { None };
            let m = material.or(part.material).unwrap_or_default();
            objects.push(
                Object::new(Arc::new(part.mesh), m, transform)?
                    .with_back_material(back_material)
                    .with_maps(maps)?,
            );
        }
        self.objects.extend(objects);
        Ok(n)
    }

    /// Adds a light.
    pub fn add_light(&mut self, light: impl Into<Light>) {
        self.lights.push(light.into());
    }

    /// Two-sided lighting (OpenGL's `GL_LIGHT_MODEL_TWO_SIDE`): back faces (clockwise on
    /// screen) are lit with the flipped normal. Off by default: they are lit with the normal
    /// as given.
    pub fn set_two_sided(&mut self, on: bool) {
        self.two_sided = on;
    }

    /// Whether back faces are lit with the flipped normal.
    pub fn two_sided(&self) -> bool {
        self.two_sided
    }

    /// The local viewer (default, `true`): `v` points from each surface point to the eye.
    /// `false` is OpenGL's infinite viewer: `v` is the constant direction toward the eye
    /// along the view axis.
    pub fn set_local_viewer(&mut self, local: bool) {
        self.infinite_viewer = !local;
    }

    /// Whether the viewer is local.
    pub fn local_viewer(&self) -> bool {
        !self.infinite_viewer
    }

    /// Sets (or with `None` removes) the fog.
    pub fn set_fog(&mut self, fog: Option<Fog>) {
        self.fog = fog;
    }

    /// The fog, if any.
    pub fn fog(&self) -> Option<&Fog> {
        self.fog.as_ref()
    }

    /// Sets or removes the environment: the light arriving from every direction, read by
    /// reflections and refractions and shown as the background when a render asks for it.
    pub fn set_environment(&mut self, environment: Option<Environment>) {
        self.environment = environment;
    }

    /// The environment, if any.
    pub fn environment(&self) -> Option<&Environment> {
        self.environment.as_ref()
    }

    /// Whether any object's material (either side) reflects or transmits light: the
    /// scenes that need the secondary stage ([`crate::reflect`]).
    pub fn has_optics(&self) -> bool {
        self.objects.iter().any(|o| {
            [o.material(), o.material_for(true, self.two_sided)]
                .iter()
                .any(|m| m.is_reflective() || m.is_transparent())
        })
    }

    /// The global ambient.
    pub fn ambient(&self) -> Vec3 {
        self.ambient
    }

    /// The objects, in submission order.
    pub fn objects(&self) -> &[Object] {
        &self.objects
    }

    /// The lights.
    pub fn lights(&self) -> &[Light] {
        &self.lights
    }

    /// The objects, to remove, replace or reorder them (each one was validated when built).
    pub fn objects_mut(&mut self) -> &mut Vec<Object> {
        &mut self.objects
    }

    /// The lights, to remove, replace or reorder them.
    pub fn lights_mut(&mut self) -> &mut Vec<Light> {
        &mut self.lights
    }

    /// Point sources each shaded point evaluates: an area light counts its points.
    pub fn light_source_count(&self) -> usize {
        self.lights
            .iter()
            .map(|l| match l {
                Light::Area(a) => a.n_points(),
                _ => 1,
            })
            .sum()
    }

    /// Total triangle count over all objects.
    pub fn triangle_count(&self) -> usize {
        self.objects.iter().map(|o| o.mesh.triangle_count()).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::primitives;

    #[test]
    fn back_material_is_used_only_for_back_faces_under_two_sided_lighting() {
        let (gold, ruby) = (
            Material::preset("gold").unwrap(),
            Material::preset("ruby").unwrap(),
        );
        let mesh = Arc::new(primitives::plane());
        let plain = Object::new(mesh.clone(), gold, Mat4::IDENTITY).unwrap();
        assert_eq!(plain.back_material(), None);
        for (back, two) in [(false, false), (true, false), (false, true), (true, true)] {
            assert_eq!(plain.material_for(back, two), &gold);
        }
        let both = plain.with_back_material(Some(ruby));
        assert_eq!(both.back_material(), Some(&ruby));
        assert_eq!(both.material_for(true, true), &ruby);
        assert_eq!(both.material_for(true, false), &gold);
        assert_eq!(both.material_for(false, true), &gold);
    }

    #[test]
    fn obj_parts_keep_their_materials_unless_overridden() {
        let ruby = Material::preset("ruby").unwrap();
        let parts = || {
            vec![
                crate::obj::ObjPart {
                    name: "a".into(),
                    mesh: primitives::plane(),
                    material: Some(ruby),
                    maps: None,
                },
                crate::obj::ObjPart {
                    name: "b".into(),
                    mesh: primitives::cube(),
                    material: None,
                    maps: None,
                },
            ]
        };
        let mut s = Scene::new(Vec3::ZERO).unwrap();
        assert_eq!(
            s.add_obj_parts(parts(), None, None, Mat4::IDENTITY)
                .unwrap(),
            2
        );
        assert_eq!(s.objects()[0].material(), &ruby);
        assert_eq!(s.objects()[1].material(), &Material::default());
        let gold = Material::preset("gold").unwrap();
        let t = Mat4::from_translation(Vec3::X);
        s.add_obj_parts(parts(), Some(gold), Some(ruby), t).unwrap();
        assert!(s.objects()[2..].iter().all(|o| o.material() == &gold
            && o.back_material() == Some(&ruby)
            && o.transform() == t));
        // A bad transform adds nothing.
        assert!(s.add_obj_parts(parts(), None, None, Mat4::ZERO).is_err());
        assert_eq!(s.objects().len(), 4);
    }
}
