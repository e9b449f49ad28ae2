//! Light scattered inside translucent solids (`scene::Material::scattering`, glTF's
//! `KHR_materials_volume_scatter`): wax, jade, marble, skin. Inside such a solid a path is
//! absorbed (σa) and scattered (σs) as it goes, the extinction σt = σa + σs; the photon pass
//! walks it from scattering to scattering (Henyey–Greenstein phase) until it reaches a
//! surface, where the photon lands as on any other (`cpu::kernels::photon_pass`). Light
//! samples, which never walk, see what is not scattered away: exp(−σt·d).
//!
//! Inside murky glass (solid glass that scatters: murky water, smoky glass,
//! `scene::Material::has_murky_glass`) eye paths pass in through the clear surface, so the
//! light scattered inside is gathered where it scatters: volume photon mapping in SPPM (after
//! Jensen and Christensen 1998 and Knaus and Zwicker 2011). There a photon's walk keeps one
//! photon a step (a slot stores one a pass): one of the step's scattering events drawn
//! uniformly as they come (a reservoir of one), with its flux times σs (what scatters there:
//! `Walk::weight` after the flight) times the step's number of events, and the way it
//! travelled; where the walk reaches a surface that keeps a photon too, one of the two is
//! drawn with even odds, its flux doubled (stopping the walk at its last scattering instead,
//! to draw the flight again next pass, would favour scattering: a flight redrawn only when it
//! passes). An eye path's flight ends at its scattering event, with a volume visible point whose
//! weight is the path's over σs (`Walk::weight_over_scattering`: the in-scattered radiance
//! per unit length carries σs in the photons). The gather then sums the volume photons in a
//! sphere, each times the phase function between its way and the eye's, over the volume of
//! the sphere's share inside the medium (`render::volume_boundary`), and each pixel keeps a third set of statistics for them, whose radius shrinks as
//! R' = R·((N + αM)/(N + M))^⅓ (`cpu::kernels::gather_update`). Volume visible points take no
//! light samples: light reaching murky glass from outside comes through its specular surface,
//! which shadow rays cannot follow, so photons there carry the direct light too.
//!
//! Where a scattering event falls is drawn by one colour channel's σt, chosen with equal
//! probability the first time a path walks, and the path's walks weighed against all three's
//! densities ([`Walk`]): one walk over the whole path, however many steps (and passes) it
//! takes, so the weights stay bounded. Photon slots carry its hero and densities from pass to
//! pass (`buffers::PathSlot::walk_hero`, `walk_densities`), its weight folded into their flux
//! at the end of each step ([`Walk::take_weight`]).

use glam::Vec3;
use scene::Material;

use crate::medium::NO_MEDIUM;
use crate::sampling::about_axis;

/// Scatterings a walk takes in one step of a photon path (one kernel invocation) before it
/// stops where it is, to go on next pass (the step counts as a bounce towards the path's
/// length; its weight is handed to the path's flux, and the walk resumes from the slot's hero
/// and densities); the path tracer's steps count so too. A photon pass's invocations
/// wait for their longest walk (a SIMD group runs together): this bounds the wait, and light
/// is not lost to a cap.
pub const SCATTERINGS_PER_STEP: u32 = 16;

/// A path's walk hero before it first walks ([`Walk::resume`]): the first scattering solid it
/// meets draws one.
pub const NO_WALK: u32 = u32::MAX;

/// The solid of `medium` (a material id, or [`NO_MEDIUM`]) where it scatters inside: where a
/// path in that medium walks.
pub fn scattering_solid(materials: &[Material], medium: u32) -> Option<&Material> {
    (medium != NO_MEDIUM)
        .then(|| &materials[medium as usize])
        .filter(|m| m.interior_scattering().max_element() > 0.0)
}

/// The volume photons' first gather radius over the surfaces' where the scene has murky
/// glass. Volume photons are sparser in a sphere than surface photons on a disc of the same
/// radius (on `scenes/cornell-murky.gltf`, about a fifteenth as many a gather), so their
/// estimates are far noisier. A larger sphere finds more, at the price of more bias where
/// the light in it is not even (`crate::volume_boundary` takes out most of the bias where it
/// reaches out of the medium); the volume photons have a grid of their own (`crate::hash`),
/// so the surfaces' cells do not grow with it. Measured at 128², four seeds × 400 passes
/// (docs/BENCHMARKS.md, session 41), 1.6 → 2.5: the media's pixel noise a third lower (full
/// lists) or an eighth (stochastic hash), the water 0.5–0.8 % darker, the relMSE against the
/// path tracer 7–11 % lower on `scenes/cornell-murky.gltf` and a thick variant, the render
/// 0–5 % slower; 4 is noisier still in error with full lists (more bias).
pub const VOLUME_RADIUS_SHARE: f32 = 2.5;

/// The volume photons' first gather radius for `scene` whose surfaces' is `radius`:
/// [`VOLUME_RADIUS_SHARE`] of it where the scene has murky glass, else the same (never used).
pub fn initial_volume_radius(scene: &scene::Scene, radius: f32) -> f32 {
    if scene.materials.iter().any(|m| m.has_murky_glass()) {
        radius * VOLUME_RADIUS_SHARE
    } else {
        radius
    }
}

/// The murky glass of `medium` (`scene::Material::has_murky_glass`): where photons are kept
/// as they scatter and eye paths end where they scatter.
pub fn murky_glass(materials: &[Material], medium: u32) -> Option<&Material> {
    scattering_solid(materials, medium).filter(|m| m.has_murky_glass())
}

/// A random walk through scattering media: the distances to its scattering events drawn by
/// one colour channel's extinction (its hero, chosen once for the path), and its weight the
/// walk's value over the mean of the three channels' densities of drawing it (the balance
/// heuristic over the path's whole walk, as pbrt-v4 weighs spectral paths): each channel's weight
/// stays below 3 × its albedo's power, however long the walk and however the channels'
/// rates differ (weighing each flight by itself instead, the weights' product over 40
/// flights in a coloured medium is so heavy-tailed that 64 passes saw half the red light).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Walk {
    hero: usize,
    /// The walk's value so far over the mean density (the light's multiplier).
    weight: Vec3,
    /// Each channel's density of drawing the walk so far over their mean (mean 1).
    densities: Vec3,
}

impl Walk {
    /// A walk whose hero channel `u` chooses, each with probability ⅓.
    pub fn start(u: f32) -> Walk {
        Walk {
            hero: ((u * 3.0) as usize).min(2),
            weight: Vec3::ONE,
            densities: Vec3::ONE,
        }
    }

    /// The walk of a path that has walked before, its hero `hero` and its channels'
    /// densities `densities` (over their mean), its weight since handed to the path
    /// ([`Walk::take_weight`]); `None` where `hero` is [`NO_WALK`].
    pub fn resume(hero: u32, densities: Vec3) -> Option<Walk> {
        (hero != NO_WALK).then(|| Walk {
            hero: (hero as usize).min(2),
            weight: Vec3::ONE,
            densities,
        })
    }

    /// The hero channel (0–2), which a path keeps for all its walks.
    pub fn hero(&self) -> u32 {
        self.hero as u32
    }

    /// Each channel's density of drawing the walk so far over their mean.
    pub fn densities(&self) -> Vec3 {
        self.densities
    }

    /// What the walk multiplies the light it carries by.
    pub fn weight(&self) -> Vec3 {
        self.weight
    }

    /// The weight so far, handed to the path's throughput at the end of a step: the walk
    /// goes on from weight 1 with its hero and densities, so the path's steps multiply to
    /// the whole walk's balance heuristic (restarting the walk each step instead multiplies
    /// weights of up to 3 each: heavy-tailed, coloured fireflies in strongly coloured media).
    pub fn take_weight(&mut self) -> Vec3 {
        std::mem::replace(&mut self.weight, Vec3::ONE)
    }

    /// The weight after a flight that ended at a scattering event, over the medium's
    /// `scattering` σs (0 in a channel that does not scatter): the transmittance to the event
    /// over the density of drawing it, which an eye path's volume visible point carries (the
    /// photons there carry σs).
    pub fn weight_over_scattering(&self, scattering: Vec3) -> Vec3 {
        Vec3::select(
            scattering.cmpgt(Vec3::ZERO),
            self.weight / scattering.max(Vec3::splat(f32::MIN_POSITIVE)),
            Vec3::ZERO,
        )
    }

    /// The next flight over a segment of `distance` in a medium of `extinction` σt and
    /// `scattering` σs, drawn by `u` (exponential in the hero's σt): the distance to the
    /// scattering event, or `None` where the walk reaches the segment's end. The weight
    /// takes the flight's value (σs·exp(−σt·t), or exp(−σt·d) passing) and each channel's
    /// density of it (σt·exp(−σt·t), or exp(−σt·d)).
    pub fn flight(
        &mut self,
        extinction: Vec3,
        scattering: Vec3,
        distance: f32,
        u: f32,
    ) -> Option<f32> {
        let rate = extinction[self.hero];
        let t = if rate > 0.0 {
            -(1.0 - u).ln() / rate
        } else {
            f32::INFINITY
        };
        let (value, density, scattered) = if t < distance {
            let kept = (-extinction * t).exp();
            (scattering * kept, extinction * kept, Some(t))
        } else {
            let kept = (-extinction * distance).exp();
            (kept, kept, None)
        };
        let densities = self.densities * density;
        let mean = densities.element_sum() / 3.0;
        if mean > 0.0 {
            self.weight *= value / mean;
            self.densities = densities / mean;
        } else {
            self.weight = Vec3::ZERO;
        }
        scattered
    }

    /// Russian roulette after a scattering event: the walk goes on with probability its
    /// weight's largest channel (at most 1), the weight divided by it; `false`: it ends.
    pub fn survives(&mut self, u: f32) -> bool {
        let survival = self.weight.max_element().min(1.0);
        if u >= survival {
            return false;
        }
        self.weight /= survival;
        true
    }
}

/// The Henyey–Greenstein phase function of asymmetry `g` at the cosine `cos` between the
/// way light travelled and the way it is scattered: (1 − g²) / (4π·(1 + g² − 2g·cos)^{3/2}),
/// per steradian.
pub fn henyey_greenstein_phase(g: f32, cos: f32) -> f32 {
    let denominator = (1.0 + g * g - 2.0 * g * cos).max(1e-12);
    (1.0 - g * g) / (4.0 * std::f32::consts::PI * denominator * denominator.sqrt())
}

/// A direction scattered from `direction` (unit) by the Henyey–Greenstein phase function of
/// asymmetry `g` (0: isotropic, towards 1: forward), drawn exactly by `u`; the phase
/// function's value over its density is 1.
pub fn henyey_greenstein(direction: Vec3, g: f32, u: [f32; 2]) -> Vec3 {
    let cos = if g.abs() < 1e-3 {
        1.0 - 2.0 * u[0]
    } else {
        let s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u[0]);
        ((1.0 + g * g - s * s) / (2.0 * g)).clamp(-1.0, 1.0)
    };
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    let phi = std::f32::consts::TAU * u[1];
    about_axis(direction, Vec3::new(sin * phi.cos(), sin * phi.sin(), cos))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Over many draws (the hero channel and the distance on a grid) one flight's weights
    /// average to the medium's true expectations: the light passing is exp(−σt·d) per
    /// channel, and the light scattered within d is σs/σt·(1 − exp(−σt·d)) per channel, for a
    /// colour whose channels differ fourfold.
    #[test]
    fn flights_average_to_the_medium_s_transmittance_and_scattering() {
        let extinction = Vec3::new(1.0, 2.0, 4.0);
        let scattering = Vec3::new(0.9, 1.0, 1.0);
        let distance = 0.7;
        let n = 400;
        let (mut passed, mut scattered, mut reached) = (Vec3::ZERO, Vec3::ZERO, Vec3::ZERO);
        for i in 0..n {
            for j in 0..n {
                let u = [(i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32];
                let mut walk = Walk::start(u[0]);
                match walk.flight(extinction, scattering, distance, u[1]) {
                    None => passed += walk.weight(),
                    Some(t) => {
                        assert!(t < distance && walk.weight().is_finite());
                        scattered += walk.weight();
                        reached += walk.weight_over_scattering(scattering);
                    }
                }
            }
        }
        let count = (n * n) as f32;
        let kept = (-extinction * distance).exp();
        let expected_scattered = scattering / extinction * (Vec3::ONE - kept);
        assert!(
            (passed / count - kept).abs().max_element() < 2e-3,
            "{} against {kept}",
            passed / count
        );
        assert!(
            (scattered / count - expected_scattered).abs().max_element() < 2e-3,
            "{} against {expected_scattered}",
            scattered / count
        );
        // Over σs: the distance travelled within d, weighed by the transmittance, ∫ exp(−σt·t).
        let expected_reached = (Vec3::ONE - kept) / extinction;
        assert!(
            (reached / count - expected_reached).abs().max_element() < 2e-3,
            "{} against {expected_reached}",
            reached / count
        );
    }

    /// A long walk in a lossless medium whose channels scatter at rates 1 : 4 : 16 keeps
    /// every channel's weight below 3 (the whole walk's balance heuristic), where weighing
    /// each flight by itself multiplies out of bounds.
    #[test]
    fn long_walks_keep_bounded_weights() {
        let extinction = Vec3::new(1.0, 4.0, 16.0);
        let mut rng = crate::rng::KernelRng::new(7, 0, 0, 0);
        for _ in 0..200 {
            let mut walk = Walk::start(rng.next_f32());
            for _ in 0..100 {
                walk.flight(extinction, extinction, f32::INFINITY, rng.next_f32());
                let weight = walk.weight();
                assert!(weight.max_element() <= 3.0 + 1e-3, "{weight}");
                assert!(weight.min_element() >= 0.0);
            }
        }
    }

    /// A walk taken in steps, each step's weight handed on (`take_weight`) and the walk
    /// resumed from its hero and densities, weighs the same as the walk taken whole.
    #[test]
    fn a_walk_in_steps_weighs_as_the_whole_walk() {
        let extinction = Vec3::new(1.0, 4.0, 16.0);
        let scattering = Vec3::new(0.9, 3.0, 15.0);
        let mut rng = crate::rng::KernelRng::new(3, 0, 0, 0);
        for _ in 0..100 {
            let hero_number = rng.next_f32();
            let (mut whole, mut stepped) = (Walk::start(hero_number), Walk::start(hero_number));
            let mut handed = Vec3::ONE;
            for flight in 0..60 {
                let (distance, u) = (rng.next_f32() * 2.0, rng.next_f32());
                let a = whole.flight(extinction, scattering, distance, u);
                let b = stepped.flight(extinction, scattering, distance, u);
                assert_eq!(a, b);
                if flight % 7 == 6 {
                    handed *= stepped.take_weight();
                    stepped = Walk::resume(stepped.hero(), stepped.densities()).unwrap();
                }
            }
            let (a, b) = (whole.weight(), handed * stepped.weight());
            assert!(
                (a - b).abs().max_element() <= 1e-4 * a.max_element().max(1e-30),
                "{a} against {b}"
            );
        }
        assert_eq!(Walk::resume(NO_WALK, Vec3::ONE), None);
    }

    /// A clear medium (σt = 0) always lets the walk pass, whole.
    #[test]
    fn a_clear_medium_lets_everything_pass() {
        for u in [[0.1, 0.2], [0.9, 0.999]] {
            let mut walk = Walk::start(u[0]);
            assert_eq!(walk.flight(Vec3::ZERO, Vec3::ZERO, 5.0, u[1]), None);
            assert_eq!(walk.weight(), Vec3::ONE);
        }
    }

    /// Henyey–Greenstein's mean cosine is g, and its draws are unit vectors; g = 0 is
    /// uniform over the sphere (mean cosine 0, mean squared 1/3).
    #[test]
    fn henyey_greenstein_has_mean_cosine_g() {
        let direction = Vec3::new(0.3, -0.5, 0.81).normalize();
        for g in [0.0, 0.4, -0.6, 0.9] {
            let n = 300;
            let (mut mean, mut square) = (0.0f64, 0.0f64);
            for i in 0..n {
                for j in 0..n {
                    let u = [(i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32];
                    let out = henyey_greenstein(direction, g, u);
                    assert!((out.length() - 1.0).abs() < 1e-4);
                    let cos = out.dot(direction) as f64;
                    mean += cos;
                    square += cos * cos;
                }
            }
            let count = (n * n) as f64;
            assert!(
                (mean / count - g as f64).abs() < 2e-3,
                "g {g}: {}",
                mean / count
            );
            if g == 0.0 {
                assert!((square / count - 1.0 / 3.0).abs() < 2e-3);
            }
        }
    }

    /// The phase function integrates to 1 over the sphere, and its mean cosine is g.
    #[test]
    fn henyey_greenstein_phase_is_normalised_with_mean_cosine_g() {
        for g in [0.0f32, 0.5, -0.3, 0.8] {
            let n = 200_000;
            let (mut total, mut mean) = (0.0f64, 0.0f64);
            for i in 0..n {
                let cos = -1.0 + 2.0 * (i as f64 + 0.5) / n as f64;
                let p = henyey_greenstein_phase(g, cos as f32) as f64;
                // dω = 2π d(cos) over the sphere.
                total += p * 2.0 * std::f64::consts::PI * 2.0 / n as f64;
                mean += cos * p * 2.0 * std::f64::consts::PI * 2.0 / n as f64;
            }
            assert!((total - 1.0).abs() < 1e-3, "g {g}: {total}");
            assert!((mean - g as f64).abs() < 1e-3, "g {g}: {mean}");
        }
    }
}
