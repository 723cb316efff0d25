//! Recordings made by the rig itself, for tests, benches and a self-check of a rig: known
//! activations deform the face; its landmark vertices, turned, moved, scaled to millimetres,
//! noised and put in OpenFace's camera coordinates (x right, y down, z away from the camera),
//! are written as an OpenFace 2.0 CSV with the 3D landmark columns.

use std::fmt::Write as _;

use glam::{EulerRot, Quat, Vec3};

use crate::model::{Activations, BoundRig};

/// How the head moves and how noisy the tracker is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Motion {
    /// Millimetres per unit of the rig's mesh.
    pub scale: f32,
    /// Largest turn of the head about each axis, radians (yaw, pitch, roll).
    pub turn: Vec3,
    /// Uniform noise added to each coordinate, -noise to +noise millimetres.
    pub noise: f32,
    /// Seed of the noise.
    pub seed: u64,
}

impl Default for Motion {
    fn default() -> Motion {
        Motion {
            scale: 12.5,
            turn: Vec3::new(0.3, 0.2, 0.1),
            noise: 0.02,
            seed: 7,
        }
    }
}

/// A small deterministic noise source, -1 to 1.
struct Noise(u64);

impl Noise {
    fn next(&mut self) -> f32 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 40) as f32 / (1u64 << 24) as f32) * 2.0 - 1.0
    }
}

/// The tracked landmarks of each pose (`None`: a frame the tracker lost), the head moving
/// through the recording as `motion` says.
pub fn landmarks(
    bound: &BoundRig,
    vertices: &[u32],
    poses: &[Option<Activations>],
    motion: Motion,
) -> Vec<Option<Vec<Vec3>>> {
    let mut noise = Noise(motion.seed);
    let mut out = Vec::new();
    let count = poses.len().max(1) as f32;
    poses
        .iter()
        .enumerate()
        .map(|(k, pose)| {
            let act = pose.as_ref()?;
            bound.deform(act, &mut out).ok()?;
            let t = k as f32 / count;
            let turn = Quat::from_euler(
                EulerRot::YXZ,
                motion.turn.x * (t * 6.0).sin(),
                motion.turn.y * (t * 4.0).cos(),
                motion.turn.z * t,
            );
            let place = Vec3::new(20.0 * t, -10.0, 600.0 - 80.0 * t);
            Some(
                vertices
                    .iter()
                    .map(|&v| {
                        let p = turn * out[v as usize] * motion.scale;
                        let jitter = Vec3::new(noise.next(), noise.next(), noise.next());
                        Vec3::new(p.x, -p.y, -p.z) + place + jitter * motion.noise
                    })
                    .collect(),
            )
        })
        .collect()
}

/// An OpenFace CSV of tracked frames (`None`: a row with `success` 0), 30 frames a second.
pub fn csv(frames: &[Option<Vec<Vec3>>]) -> String {
    let mut text = String::from("frame, face_id, timestamp, confidence, success");
    for axis in ["X", "Y", "Z"] {
        for i in 0..crate::landmarks::COUNT {
            let _ = write!(text, ", {axis}_{i}");
        }
    }
    text.push_str(", AU12_r\n");
    for (k, frame) in frames.iter().enumerate() {
        let success = u8::from(frame.is_some());
        let _ = write!(
            text,
            "{}, 0, {:.3}, 0.98, {success}",
            k + 1,
            k as f64 / 30.0
        );
        let points = frame
            .clone()
            .unwrap_or_else(|| vec![Vec3::ZERO; crate::landmarks::COUNT]);
        for axis in 0..3 {
            for p in &points {
                let _ = write!(text, ", {:.3}", p[axis]);
            }
        }
        text.push_str(", 0\n");
    }
    text
}
