//! The attention's vote matrices (Sjöö et al. `004` §3.2) on a simulated image; the model is
//! in the [parent module's documentation](super).

use super::{cell_cover, face_image, mix, name_hash, FaceImage, ImageModel, ImageScene};
use avs_robot::{Camera, ImageGeometry, ViewCone, VoteMatrix};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal, Poisson};

/// One background structure: centre in pixels, radius in pixels, strength in `[0, 1]`.
#[derive(Debug, Clone, Copy)]
struct Blob {
    u: f64,
    v: f64,
    radius: f64,
    strength: f64,
}

/// One vote matrix per class of `classes` (in that order) for the image of `scene` taken
/// through `cone` by `camera`: the similarity of every vote cell to the class, in `[0, 1]`
/// (see the [module documentation](super)). Draws one number from `rng` (the image's seed);
/// the same seed gives the same matrices.
pub fn attention<R: Rng>(
    model: &ImageModel,
    scene: &ImageScene,
    camera: &Camera,
    cone: &ViewCone,
    image: &ImageGeometry,
    classes: &[String],
    rng: &mut R,
) -> Vec<VoteMatrix> {
    let seed: u64 = rng.gen();
    let (cols, rows) = (image.cols(), image.rows());
    let blobs = background_blobs(model, scene, camera, cone, image, seed);
    // The objects in the image, farthest first: nearer ones are painted over them.
    let mut faces: Vec<(usize, FaceImage)> = scene
        .objects
        .iter()
        .enumerate()
        .filter_map(|(i, o)| face_image(o, camera, cone, image).map(|f| (i, f)))
        .collect();
    faces.sort_by(|a, b| b.1.depth.total_cmp(&a.1.depth));
    let bg = &scene.background;
    let amplitude = ImageModel::by_clutter(model.clutter_amplitude, bg.clutter) * bg.depth.max(0.0)
        / (bg.depth.max(0.0) + model.clutter_depth_half);
    let noise = Normal::new(0.0, model.vote_noise.max(0.0)).expect("a finite deviation");
    classes
        .iter()
        .map(|class| {
            let class_seed = mix(seed ^ mix(name_hash(class)));
            let mut crng = ChaCha8Rng::seed_from_u64(class_seed);
            // How much each background structure resembles this class, and the white noise:
            // drawn before the objects, so that a cell no object touches is the same whatever
            // the objects are.
            let weights: Vec<f64> = blobs.iter().map(|_| crng.gen::<f64>()).collect();
            let white: Vec<f64> = (0..cols * rows).map(|_| noise.sample(&mut crng)).collect();
            let mut m = VoteMatrix::zeros(class.clone(), cols, rows);
            for row in 0..rows {
                for col in 0..cols {
                    let (u, v) = image.cell_centre(col, row);
                    let field: f64 = blobs
                        .iter()
                        .zip(&weights)
                        .map(|(b, w)| {
                            let d2 = (u - b.u).powi(2) + (v - b.v).powi(2);
                            b.strength * w * (-d2 / (2.0 * b.radius * b.radius)).exp()
                        })
                        .sum();
                    m.values[row * cols + col] = model.clutter_floor + amplitude * field;
                }
            }
            for &(i, ref face) in &faces {
                let o = &scene.objects[i];
                let s = model.class_similarity(class, &o.class, o.lookalike);
                let n = face.size_px();
                let n0 = model.small_object_px;
                let g = 1.0 / (1.0 + (n0 / n.max(1e-9)).powf(model.small_object_steepness));
                let a = 1.0 - model.attention_angle_loss * (1.0 - face.view_angle.cos().abs());
                let spans = face.apparent_px.0.max(face.apparent_px.1) / f64::from(image.cell_px);
                let tau = model.patch_variation * (1.0 - (-(spans - 1.0).max(0.0) / 3.0).exp());
                let q = s * g * a;
                let Some(b) = face.visible_box(image) else {
                    continue;
                };
                let c = f64::from(image.cell_px);
                let (c0, c1) = ((b[0] / c) as usize, ((b[2] / c).ceil() as usize).min(cols));
                let (r0, r1) = ((b[1] / c) as usize, ((b[3] / c).ceil() as usize).min(rows));
                if c0 >= c1 || r0 >= r1 {
                    // Only in the strips at the right and bottom edges that hold no whole cell.
                    continue;
                }
                let mut orng = ChaCha8Rng::seed_from_u64(mix(class_seed ^ mix(i as u64 + 1)));
                let patches = patch_field(c1 - c0, r1 - r0, &mut orng);
                for row in r0..r1 {
                    for col in c0..c1 {
                        let phi = cell_cover(b, col, row, image);
                        if phi <= 0.0 {
                            continue;
                        }
                        let phi = phi.powf(model.cover_exponent);
                        // Off the face's centre, a cell's receptive fields reach past the
                        // object's edge; and each cell sees its own patch of the object.
                        let (u, v) = image.cell_centre(col, row);
                        let du = (u - (face.bbox[0] + face.bbox[2]) / 2.0)
                            / ((face.bbox[2] - face.bbox[0]) / 2.0).max(1e-9);
                        let dv = (v - (face.bbox[1] + face.bbox[3]) / 2.0)
                            / ((face.bbox[3] - face.bbox[1]) / 2.0).max(1e-9);
                        let edge = ((du * du + dv * dv) / 2.0).min(1.0);
                        let t = 1.0
                            - tau * edge
                            - model.patch_noise * patches[(row - r0) * (c1 - c0) + (col - c0)];
                        let k = row * cols + col;
                        m.values[k] = phi * q * t + (1.0 - phi) * m.values[k];
                    }
                }
            }
            for (x, w) in m.values.iter_mut().zip(&white) {
                *x = (*x + w).clamp(0.0, 1.0);
            }
            m
        })
        .collect()
}

/// How poorly each cell of a `w × h` block of an object's cells matches the whole object, in
/// `[0, 1]`: uniform values averaged over 3 × 3 cells (neighbouring patches of an object look
/// alike), stretched back to fill `[0, 1]`, row by row.
fn patch_field(w: usize, h: usize, rng: &mut ChaCha8Rng) -> Vec<f64> {
    let (ew, eh) = (w + 2, h + 2);
    let raw: Vec<f64> = (0..ew * eh).map(|_| rng.gen::<f64>()).collect();
    let mut out = Vec::with_capacity(w * h);
    for row in 0..h {
        for col in 0..w {
            let mut sum = 0.0;
            for dr in 0..3 {
                for dc in 0..3 {
                    sum += raw[(row + dr) * ew + col + dc];
                }
            }
            // The mean of nine uniforms has standard deviation 0.096 about 0.5.
            out.push(((sum / 9.0 - 0.5) * 3.0 + 0.5).clamp(0.0, 1.0));
        }
    }
    out
}

/// The image's background structures, drawn from `seed` (the same for every class).
fn background_blobs(
    model: &ImageModel,
    scene: &ImageScene,
    camera: &Camera,
    cone: &ViewCone,
    image: &ImageGeometry,
    seed: u64,
) -> Vec<Blob> {
    let mut rng = ChaCha8Rng::seed_from_u64(mix(seed));
    let bg = &scene.background;
    let mean = ImageModel::by_clutter(model.clutter_blobs, bg.clutter) * bg.depth.max(0.0);
    let count = if mean > 0.0 {
        Poisson::new(mean).map_or(0.0, |p| p.sample(&mut rng)) as usize
    } else {
        0
    };
    let f = image.focal_px(camera.hfov / cone.zoom.max(1.0));
    let depth = bg.depth.max(0.1);
    let [lo, hi] = model.clutter_size;
    let (ln_lo, ln_hi) = (lo.max(1e-6).ln(), hi.max(lo).max(1e-6).ln());
    (0..count)
        .map(|_| {
            let u = rng.gen::<f64>() * f64::from(image.width_px);
            let v = rng.gen::<f64>() * f64::from(image.height_px);
            let radius_m = (ln_lo + (ln_hi - ln_lo) * rng.gen::<f64>()).exp();
            Blob {
                u,
                v,
                radius: (f * radius_m / depth).max(1.0),
                strength: rng.gen::<f64>(),
            }
        })
        .collect()
}
