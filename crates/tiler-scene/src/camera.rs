//! Cameras: view and projection matrices in tiler's clip conventions (Vulkan: y down in
//! clip space, depth 0 at the near plane and 1 at the far plane), and the placement of the
//! camera of a glTF scene after SCENES.md §3.

use glam::{DMat4, DVec3, DVec4, Mat4, Vec3};

use crate::gltf::{GltfProjection, Model};

/// A perspective camera looking from `eye` at `target`, y up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub eye: Vec3,
    pub target: Vec3,
    pub fov_y_radians: f32,
    pub near: f32,
    pub far: f32,
}

impl Camera {
    pub fn look_at(eye: Vec3, target: Vec3, fov_y_radians: f32, near: f32, far: f32) -> Camera {
        Camera { eye, target, fov_y_radians, near, far }
    }

    /// World → clip for a viewport of the given aspect (width / height): right-handed view,
    /// Vulkan projection (y down, depth in [0, 1]), so a triangle counter-clockwise seen from
    /// the front is counter-clockwise in tiler's framebuffer.
    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        let up = up_for(self.target.as_dvec3() - self.eye.as_dvec3()).as_vec3();
        let view = glam::camera::rh::view::look_at_mat4(self.eye, self.target, up);
        let proj = glam::camera::rh::proj::vulkan::perspective(self.fov_y_radians, aspect, self.near, self.far);
        proj * view
    }
}

/// Which camera looks at a glTF scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CameraChoice {
    /// `Interior` for files whose name starts with `sponza` or `atrium` (any case), else `Orbit`
    /// (SCENES.md §3 `--camera auto`).
    Auto,
    /// From `C + R · (0, 0.3, 1.5)` towards the bounding box's centre `C` (`R`: half its diagonal).
    Orbit,
    /// From `min + size ⊙ (0.85, 0.2, 0.5)` towards `min + size ⊙ (0, 0.3, 0.5)`: down a
    /// courtyard that runs along x.
    Interior,
    /// The file's own camera number `n` (in the scene's traversal order).
    Gltf(usize),
    /// Explicit placement, vertical field of view in degrees.
    LookAt { eye: DVec3, target: DVec3, fov_y_degrees: f64 },
}

impl std::str::FromStr for CameraChoice {
    type Err = String;

    /// `auto`, `orbit`, `interior`, `gltf` (the first camera), `gltf:N`, or
    /// `EX,EY,EZ:TX,TY,TZ[:FOV_DEGREES]` (eye, target, vertical field of view, default 60).
    fn from_str(s: &str) -> Result<CameraChoice, String> {
        match s.to_ascii_lowercase().as_str() {
            "auto" => return Ok(CameraChoice::Auto),
            "orbit" => return Ok(CameraChoice::Orbit),
            "interior" => return Ok(CameraChoice::Interior),
            "gltf" => return Ok(CameraChoice::Gltf(0)),
            _ => {}
        }
        if let Some(n) = s.strip_prefix("gltf:") {
            return n.parse().map(CameraChoice::Gltf).map_err(|_| format!("'{n}' in '{s}' is not a camera number"));
        }
        let parts: Vec<&str> = s.split(':').collect();
        let vec3 = |p: &str| -> Result<DVec3, String> {
            let c: Vec<f64> = p
                .split(',')
                .map(|c| c.trim().parse::<f64>())
                .collect::<Result<_, _>>()
                .map_err(|_| format!("'{p}' is not three comma-separated numbers"))?;
            match c[..] {
                [x, y, z] if c.iter().all(|v| v.is_finite()) => Ok(DVec3::new(x, y, z)),
                _ => Err(format!("'{p}' is not three finite comma-separated numbers")),
            }
        };
        match parts[..] {
            [eye, target] | [eye, target, _] => {
                let fov_y_degrees = match parts.get(2) {
                    Some(f) => f.trim().parse::<f64>().map_err(|_| format!("field of view '{f}' is not a number"))?,
                    None => 60.0,
                };
                if !(fov_y_degrees > 0.0 && fov_y_degrees < 180.0) {
                    return Err(format!("field of view {fov_y_degrees}° must be between 0 and 180"));
                }
                let (eye, target) = (vec3(eye)?, vec3(target)?);
                if eye == target {
                    return Err("eye and target are the same point".into());
                }
                Ok(CameraChoice::LookAt { eye, target, fov_y_degrees })
            }
            _ => Err(format!(
                "'{s}' is not a camera: use auto, orbit, interior, gltf, gltf:N or EX,EY,EZ:TX,TY,TZ[:FOV]"
            )),
        }
    }
}

/// Where a camera stands and its world → clip matrix in GL conventions (computed in double
/// precision, each element rounded to f32 once, SCENES.md §3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// Which rule placed it (`orbit`, `interior`, `gltf 0`, `look-at`).
    pub name: &'static str,
    pub eye: DVec3,
    pub target: Option<DVec3>,
    pub near: f64,
    pub far: Option<f64>,
    /// `Proj · View`, OpenGL clip space (y up, `−w ≤ z ≤ w`).
    pub gl_view_proj: Mat4,
}

/// `v / |v|` (SCENES.md's `normalize`, a division, not a multiplication by a reciprocal).
fn normalize(v: DVec3) -> DVec3 {
    v / v.dot(v).sqrt()
}

/// The up vector for a camera looking along `forward`: y, unless the camera looks (almost)
/// straight up or down, where y is no direction at all for the picture's top and the view
/// matrix would be NaN; then −z, so the top of the picture is the far side of the scene.
pub fn up_for(forward: DVec3) -> DVec3 {
    let f = forward.normalize_or_zero();
    if f.cross(DVec3::Y).length_squared() < 1e-12 { DVec3::NEG_Z } else { DVec3::Y }
}

/// SCENES.md §3's view matrix (right-handed, looking down −z, y up; see [`up_for`] for a camera
/// looking straight up or down).
pub fn gl_look_at(eye: DVec3, target: DVec3) -> DMat4 {
    let f = normalize(target - eye);
    let s = normalize(f.cross(up_for(target - eye)));
    let u = s.cross(f);
    DMat4::from_cols(
        DVec4::new(s.x, u.x, -f.x, 0.0),
        DVec4::new(s.y, u.y, -f.y, 0.0),
        DVec4::new(s.z, u.z, -f.z, 0.0),
        DVec4::new(-s.dot(eye), -u.dot(eye), f.dot(eye), 1.0),
    )
}

/// SCENES.md §3's perspective projection (GL depth range); `far = None` is the infinite limit.
pub fn gl_perspective(fov_y_radians: f64, aspect: f64, near: f64, far: Option<f64>) -> DMat4 {
    let g = 1.0 / (fov_y_radians / 2.0).tan();
    let (m22, m23) = match far {
        Some(far) => ((far + near) / (near - far), 2.0 * far * near / (near - far)),
        None => (-1.0, -2.0 * near),
    };
    DMat4::from_cols(
        DVec4::new(g / aspect, 0.0, 0.0, 0.0),
        DVec4::new(0.0, g, 0.0, 0.0),
        DVec4::new(0.0, 0.0, m22, -1.0),
        DVec4::new(0.0, 0.0, m23, 0.0),
    )
}

/// A GL orthographic projection of half-extents `xmag`, `ymag`.
pub fn gl_orthographic(xmag: f64, ymag: f64, near: f64, far: f64) -> DMat4 {
    DMat4::from_cols(
        DVec4::new(1.0 / xmag, 0.0, 0.0, 0.0),
        DVec4::new(0.0, 1.0 / ymag, 0.0, 0.0),
        DVec4::new(0.0, 0.0, 2.0 / (near - far), 0.0),
        DVec4::new(0.0, 0.0, (far + near) / (near - far), 1.0),
    )
}

/// Places the camera for `model` in a viewport of `aspect` (width / height).
///
/// # Errors
/// A glTF camera the file does not have, or one with an unusable projection.
pub fn place(model: &Model, choice: CameraChoice, aspect: f64) -> Result<Placement, String> {
    let (min, max) = (model.min, model.max);
    let centre = (min + max) * 0.5;
    let radius = 0.5 * (max - min).dot(max - min).sqrt();
    let size = max - min;
    let (near, far) = (radius * 0.005, radius * 4.0);
    let fov_60 = 60f64.to_radians();
    let choice = match choice {
        CameraChoice::Auto => {
            let name = model.file_name().to_ascii_lowercase();
            if name.starts_with("sponza") || name.starts_with("atrium") {
                CameraChoice::Interior
            } else {
                CameraChoice::Orbit
            }
        }
        other => other,
    };
    let look = |name, eye: DVec3, target: DVec3, fov: f64, far: f64| {
        let vp = gl_perspective(fov, aspect, near, Some(far)) * gl_look_at(eye, target);
        Placement { name, eye, target: Some(target), near, far: Some(far), gl_view_proj: vp.as_mat4() }
    };
    Ok(match choice {
        CameraChoice::Auto => unreachable!("resolved above"),
        CameraChoice::Orbit => look("orbit", centre + radius * DVec3::new(0.0, 0.3, 1.5), centre, fov_60, far),
        CameraChoice::Interior => {
            let eye = min + size * DVec3::new(0.85, 0.2, 0.5);
            look("interior", eye, min + size * DVec3::new(0.0, 0.3, 0.5), fov_60, far)
        }
        CameraChoice::LookAt { eye, target, fov_y_degrees } => {
            if !(target - eye).is_finite() || (target - eye).length_squared() == 0.0 {
                return Err(format!("the camera's eye {eye} and target {target} must be two different points"));
            }
            let far = far.max((eye - centre).length() + 2.0 * radius);
            look("look-at", eye, target, fov_y_degrees.to_radians(), far)
        }
        CameraChoice::Gltf(n) => {
            let camera = model.cameras.get(n).ok_or_else(|| {
                format!(
                    "{}: has {} camera(s) in its scene, so there is no camera {n}",
                    model.file_name(),
                    model.cameras.len()
                )
            })?;
            let view = camera.world.inverse();
            if !view.is_finite() {
                return Err(format!("{}: camera {n}'s node matrix cannot be inverted", model.file_name()));
            }
            let (proj, near, far) = match camera.projection {
                GltfProjection::Perspective { yfov_radians, znear, zfar, .. } => {
                    (gl_perspective(yfov_radians, aspect, znear, zfar), znear, zfar)
                }
                GltfProjection::Orthographic { xmag, ymag, znear, zfar } => {
                    (gl_orthographic(xmag, ymag, znear, zfar), znear, Some(zfar))
                }
            };
            let vp = proj * view;
            if !vp.is_finite() {
                return Err(format!("{}: camera {n} has an unusable projection", model.file_name()));
            }
            let eye = camera.world.transform_point3(DVec3::ZERO);
            Placement { name: "gltf", eye, target: None, near, far, gl_view_proj: vp.as_mat4() }
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn camera_choices_parse() {
        assert_eq!("auto".parse::<CameraChoice>().unwrap(), CameraChoice::Auto);
        assert_eq!("gltf".parse::<CameraChoice>().unwrap(), CameraChoice::Gltf(0));
        assert_eq!("gltf:2".parse::<CameraChoice>().unwrap(), CameraChoice::Gltf(2));
        assert_eq!(
            "0,1,3:0,0,0:45".parse::<CameraChoice>().unwrap(),
            CameraChoice::LookAt { eye: DVec3::new(0.0, 1.0, 3.0), target: DVec3::ZERO, fov_y_degrees: 45.0 }
        );
        for bad in ["", "somewhere", "0,1:0,0,0", "0,0,0:0,0,0", "0,1,3:0,0,0:200", "1,2,nan:0,0,0"] {
            assert!(bad.parse::<CameraChoice>().is_err(), "{bad}");
        }
    }

    #[test]
    fn look_at_and_perspective_follow_scenes_md() {
        // Looking down −z from +z: the view matrix is a translation.
        let view = gl_look_at(DVec3::new(0.0, 0.0, 5.0), DVec3::ZERO);
        assert_eq!(view.transform_point3(DVec3::new(1.0, 2.0, 0.0)), DVec3::new(1.0, 2.0, -5.0));
        // The near plane maps to z = −w, the far plane to z = w.
        let proj = gl_perspective(60f64.to_radians(), 2.0, 1.0, Some(10.0));
        let near = proj * DVec4::new(0.0, 0.0, -1.0, 1.0);
        let far = proj * DVec4::new(0.0, 0.0, -10.0, 1.0);
        assert!((near.z / near.w + 1.0).abs() < 1e-12 && (far.z / far.w - 1.0).abs() < 1e-12);
        assert!((proj.x_axis.x * 2.0 - proj.y_axis.y).abs() < 1e-12);
    }

    #[test]
    fn a_camera_looking_straight_down_or_up_has_a_finite_view() {
        for target in [DVec3::new(0.0, -3.0, 0.0), DVec3::new(0.0, 7.0, 0.0)] {
            let view = gl_look_at(DVec3::ZERO, target);
            assert!(view.is_finite(), "{view}");
            // The target is straight ahead, on the −z axis of the view.
            let t = view.transform_point3(target);
            assert!(t.x.abs() < 1e-12 && t.y.abs() < 1e-12 && t.z < 0.0, "{t}");
            let camera = Camera::look_at(Vec3::ZERO, target.as_vec3(), 1.0, 0.1, 10.0);
            assert!(camera.view_proj(1.0).is_finite());
        }
        // An ordinary camera keeps y up.
        assert_eq!(up_for(DVec3::new(0.0, -1.0, -1.0)), DVec3::Y);
    }
}
