//! The recogniser's feature matches (Sjöö et al. `004` §3.3.2, §3.5) on a simulated image;
//! the model is in the [parent module's documentation](super).

use super::{face_image, ClassAppearance, ImageModel, ImageScene};
use avs_robot::{Camera, FeatureMatch, ImageGeometry, ViewCone};
use rand::Rng;
use rand_distr::{Binomial, Distribution, Normal, Poisson};

/// What the recogniser found for one class on one image.
#[derive(Debug, Clone, PartialEq)]
pub struct Recognition {
    /// Features in the class's model.
    pub model_features: u32,
    /// The matched features, true matches and mismatches together, in no particular order.
    pub matches: Vec<FeatureMatch>,
}

/// Match `class`'s model in the image of `scene` taken through `cone` by `camera` (see the
/// [module documentation](super)), drawing from `rng`.
pub fn recognition<R: Rng>(
    model: &ImageModel,
    scene: &ImageScene,
    camera: &Camera,
    cone: &ViewCone,
    image: &ImageGeometry,
    class: &ClassAppearance,
    rng: &mut R,
) -> Recognition {
    let n_model = model.model_features;
    let (w_tr, _) = class.train_px(image);
    let mut matches = Vec::new();
    for o in scene.objects.iter().filter(|o| o.class == class.name) {
        let Some(face) = face_image(o, camera, cone, image) else {
            continue;
        };
        let Some(b) = face.visible_box(image) else {
            continue;
        };
        let n = face.size_px();
        let p = model.match_share(n, face.view_angle) * face.visible_share(image);
        let count = Binomial::new(u64::from(n_model), p).map_or(0, |d| d.sample(rng));
        // The apparent scale relative to the training image: a keypoint's scale follows the
        // object's pixels per metre, here `f / depth`, there `W_tr / W` (whichever side of the
        // object the face is).
        let ratio = face.apparent_px.0 / o.width.max(1e-9) * class.width / w_tr;
        let sd = model.scale_noise + model.small_scale_noise * (model.detail_px / n).powi(2);
        let noise = Normal::new(0.0, sd.min(2.0)).expect("a finite deviation");
        for _ in 0..count {
            matches.push(FeatureMatch {
                u: rng.gen_range(b[0]..b[2]),
                v: rng.gen_range(b[1]..b[3]),
                scale_ratio: ratio * noise.sample(rng).exp(),
            });
        }
    }
    // Mismatches from the background.
    let mean = ImageModel::by_clutter(model.mismatches, scene.background.clutter);
    let count = if mean > 0.0 {
        Poisson::new(mean).map_or(0.0, |p| p.sample(rng)) as usize
    } else {
        0
    };
    // The distance at which the class's face fills its training width at zoom 1: a scale
    // ratio `ρ` puts it at `fill / ρ`.
    let fill = class.width * image.focal_px(camera.hfov) / w_tr;
    for _ in 0..count {
        let [lo, hi] = if rng.gen::<f64>() < model.close_mismatch_share {
            model.close_mismatch_distance
        } else {
            model.far_mismatch_distance
        };
        let (ln_lo, ln_hi) = (lo.max(1e-3).ln(), hi.max(lo).max(1e-3).ln());
        let distance = (ln_lo + (ln_hi - ln_lo) * rng.gen::<f64>()).exp();
        matches.push(FeatureMatch {
            u: rng.gen::<f64>() * f64::from(image.width_px),
            v: rng.gen::<f64>() * f64::from(image.height_px),
            scale_ratio: fill / distance,
        });
    }
    Recognition {
        model_features: n_model,
        matches,
    }
}
