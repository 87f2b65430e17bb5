//! The orbit camera: a target, a distance and two angles (z up, metres).

use glam::{Mat4, Vec3};

/// Preset views (`softgrip screenshot --view`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum View {
    /// Looking along +y (from the front, -y side).
    Front,
    /// Looking along -x (from the +x side).
    Side,
    /// Looking down -z.
    Top,
    /// From the front right, above.
    Iso,
}

/// An orbit camera: looks at `target` from `distance` away, at angles `yaw` and `pitch`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// The point looked at and orbited about, world m.
    pub target: Vec3,
    /// Distance from the target (m).
    pub distance: f32,
    /// Rotation about z, radians; 0 = looking along +y.
    pub yaw: f32,
    /// Elevation, radians; pi/2 = straight down.
    pub pitch: f32,
    /// Vertical field of view, radians.
    pub fov_y: f32,
}

impl Camera {
    /// A camera on `view` that shows the box `[min, max]` whole in an
    /// image at least as wide as it is tall.
    pub fn framing(min: Vec3, max: Vec3, view: View) -> Camera {
        Camera::framing_aspect(min, max, view, 1.0)
    }

    /// A camera on `view` that shows the box `[min, max]` whole in an
    /// image of this width / height.
    pub fn framing_aspect(min: Vec3, max: Vec3, view: View, aspect: f32) -> Camera {
        let (yaw, pitch) = match view {
            View::Front => (0.0, 0.0),
            View::Side => (std::f32::consts::FRAC_PI_2, 0.0),
            View::Top => (0.0, std::f32::consts::FRAC_PI_2),
            View::Iso => (35f32.to_radians(), 30f32.to_radians()),
        };
        let fov_y = 40f32.to_radians();
        let radius = 0.5 * (max - min).length().max(1e-6);
        // The narrower of the two fields of view must hold the sphere
        // around the box.
        let half = (0.5 * fov_y).tan();
        let narrow = (half * aspect.clamp(0.05, 1.0)).atan();
        Camera {
            target: 0.5 * (min + max),
            distance: 1.15 * radius / narrow.sin(),
            yaw,
            pitch,
            fov_y,
        }
    }

    /// Where the camera is.
    pub fn eye(&self) -> Vec3 {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        self.target + self.distance * Vec3::new(cp * sy, -cp * cy, sp)
    }

    fn up(&self) -> Vec3 {
        if self.pitch.abs() > 89f32.to_radians() {
            // Looking straight down: screen up is the view's forward.
            let (sy, cy) = self.yaw.sin_cos();
            Vec3::new(-sy, cy, 0.0) * self.pitch.signum()
        } else {
            Vec3::Z
        }
    }

    /// World to clip space (depth 0..1, as wgpu wants).
    pub fn view_projection(&self, aspect: f32) -> Mat4 {
        let near = (self.distance * 0.01).max(1e-5);
        let far = self.distance * 10.0 + 1.0;
        // Depth 0..1 and y up in clip space: the DirectX/WebGPU convention.
        glam::camera::rh::proj::directx::perspective(self.fov_y, aspect, near, far)
            * glam::camera::rh::view::look_at_mat4(self.eye(), self.target, self.up())
    }

    /// The pixel (x right, y down) a world point lands on in a `width` x
    /// `height` image, if it is in front of the camera.
    pub fn project(&self, p: Vec3, width: u32, height: u32) -> Option<(f32, f32)> {
        let clip = self.view_projection(width as f32 / height as f32) * p.extend(1.0);
        if clip.w <= 0.0 {
            return None;
        }
        let ndc = clip.truncate() / clip.w;
        Some((
            (ndc.x + 1.0) * 0.5 * width as f32,
            (1.0 - ndc.y) * 0.5 * height as f32,
        ))
    }
}
