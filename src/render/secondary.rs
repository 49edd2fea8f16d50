//! The effects past ray casting (seed 004's course onwards): lights with shadow rays, mirror and
//! glass rays up to a depth limit, ambient occlusion and antialiasing, each computed only when the
//! scene declares it. The primary ray through each pixel's centre is cast and counted as ray casting
//! alone does (so [`Stats`]' first counters mean the same with or without effects); every other ray
//! is counted by kind in [`Stats::secondary`].
//!
//! Secondary rays start off the surface: moved by `settings.offset` along the normal, to the side
//! they leave by. Without that ([`Bug::ShadowAcne`]) a rounded hit point below its surface sees the
//! surface itself at t ≈ 1e-16: shadow acne.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hash, Hasher};

use rand_pcg::Pcg32;

use super::Bug;
use super::Hit;
use super::cast;
use super::objects::unit;
use super::ray_kinds::RayKind;
use super::shading::light::{incoming, lambert};
use super::shading::optics::{reflect, refract, schlick};
use super::shading::sampling::{cosine_hemisphere, pixel_rng, stratified};
use super::shading::shade::{Shader, Surface};
use super::{Basis, Prepared, Ray, Stats, camera_ray_at, pinhole_basis};
use crate::math::linalg::{V3, dot};
use crate::scene::render::Light;
use crate::scene::render::{Effect, Material};

mod ahead;

/// True when the scene calls for an effect past ray casting, or has lights to shade by.
pub fn applies(prepared: &Prepared) -> bool {
    let on = |e: Effect| prepared.effects.contains(&e);
    Effect::PAST_CASTING.into_iter().any(on)
        || (!prepared.lighting.lights.is_empty()
            && (on(Effect::FacingRatio) || on(Effect::SmoothNormals)))
}

/// Which effects are on, decided once per render.
#[derive(Clone, Copy, Debug)]
struct Effects {
    shadows: bool,
    reflections: bool,
    refraction: bool,
    occlusion: bool,
    antialiasing: bool,
}

/// How a light reaches a hit, as the ray tree tells it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightTest {
    /// The surface faces away from the light: no ray is cast.
    FacesAway,
    /// Lit, not tested: `shadows` is off.
    Untested,
    /// The shadow ray `(origin, direction)` up to `t_max` found nothing in the way.
    Lit(Ray, f64),
    /// The shadow ray `(origin, direction)` up to `t_max` was blocked.
    Blocked(Ray, f64),
}

/// What a pixel's rays do, told as they are cast: the probe's ray tree listens
/// ([`super::inspect::ray_tree`]); a render passes [`Silent`], which the compiler removes.
pub trait Record {
    /// A reflected, refracted or sample ray of `kind` starts at bounce `depth`.
    fn start(&mut self, _kind: RayKind, _depth: u32, _ray: Ray) {}
    /// The started ray's nearest hit.
    fn met(&mut self, _hit: Option<Hit>) {}
    /// The started ray brings back `colour`, and ends.
    fn end(&mut self, _colour: V3<f64>) {}
    /// How light `index` reaches the current ray's hit.
    fn light(&mut self, _index: usize, _test: LightTest) {}
    /// The current hit's ambient-occlusion rays: `cast` of them, `blocked` found something.
    fn occlusion(&mut self, _cast: u32, _blocked: u32) {}
    /// The shadow or occlusion rays told of next (until the next call) are cast together.
    fn any_hits_together(&mut self) {}
    /// The shadow rays told of next were cast ahead with neighbouring hits' (a band's first hits,
    /// [`SecondaryCaster::shade_band`]): `starts`, the first of their packet; otherwise they go on
    /// the packet of the rays cast ahead before them.
    fn any_hits_ahead(&mut self, starts: bool) {
        if starts {
            self.any_hits_together();
        }
    }
    /// A band's pixel is shaded next, its centre ray along `centre`
    /// ([`SecondaryCaster::shade_band`]).
    fn pixel(&mut self, _centre: Ray) {}
    /// A shadow or occlusion ray (`kind`) asks whether anything lies on it within (0, t_max).
    fn any_hit_query(&mut self, _kind: RayKind, _ray: Ray, _t_max: f64) {}
    /// The nearest hit (t in (0, ∞)) of `ray` where it was cast ahead, together with its
    /// neighbours' (a render's mirror and glass rays, `FoundAhead`); `None`: cast it now.
    /// Listeners cast nothing ahead.
    fn cast_ahead(&mut self, _ray: &Ray) -> Option<Option<Hit>> {
        None
    }
}

/// Records nothing: a render.
pub struct Silent;

impl Record for Silent {}

/// A render's caster of secondary rays: the scene, its effects and the shader.
pub struct SecondaryCaster<'a> {
    prepared: &'a Prepared,
    shader: Shader,
    on: Effects,
    basis: Option<Basis>,
}

impl<'a> SecondaryCaster<'a> {
    /// The caster for a prepared scene.
    pub fn new(prepared: &'a Prepared) -> SecondaryCaster<'a> {
        let on = |e: Effect| prepared.effects.contains(&e);
        let lit = !prepared.lighting.lights.is_empty();
        SecondaryCaster {
            prepared,
            shader: if lit {
                Shader::lit(&prepared.effects)
            } else {
                Shader::new(&prepared.effects)
            },
            on: Effects {
                shadows: on(Effect::Shadows),
                reflections: on(Effect::Reflections),
                refraction: on(Effect::Refraction),
                occlusion: on(Effect::AmbientOcclusion),
                antialiasing: on(Effect::Antialiasing),
            },
            basis: pinhole_basis(&prepared.camera, prepared.width, prepared.height),
        }
    }

    /// Renders rows `first..` into the given slices, as [`Prepared`]'s ray caster does.
    pub fn render_rows(
        &self,
        first: usize,
        pixels: &mut [[f32; 3]],
        covered: &mut [bool],
    ) -> Stats {
        let width = self.prepared.width;
        let mut stats = Stats::default();
        let rows = first..first + pixels.len() / width;
        let primary = self
            .prepared
            .cast_rows(rows, self.basis.as_ref(), &mut stats);
        if self.on.antialiasing && cast::packets_pay(self.prepared) {
            self.sample_rows(first, &primary, pixels, &mut stats);
            for (covered, (_, hit)) in covered.iter_mut().zip(&primary) {
                *covered = hit.is_some();
            }
            return stats;
        }
        let ahead = self.cast_ahead(&primary, &mut stats);
        for (covered, (_, hit)) in covered.iter_mut().zip(&primary) {
            *covered = hit.is_some();
        }
        let put = |at: usize, colour: V3<f64>| pixels[at] = colour.map(|c| c as f32);
        self.shade_band(first, &primary, (&mut ahead.found(), &mut stats), put);
        stats
    }

    /// A pixel's colour from its centre's primary ray and hit (cast and counted by the caller).
    ///
    /// With `antialiasing` the colour is the mean of exactly k×k stratified sample rays; the centre
    /// ray still decides coverage (and is the ray the probe follows), and its surface is shaded as
    /// ray casting shades it, so ray casting's counters mean the same with or without antialiasing,
    /// but its light is not gathered: no shadow, mirror, glass or occlusion ray starts from it.
    pub fn pixel(
        &self,
        at: (usize, usize),
        centre: Ray,
        hit: Option<Hit>,
        stats: &mut Stats,
    ) -> V3<f64> {
        self.pixel_told(at, (centre, hit), &mut Silent, stats)
    }

    /// [`SecondaryCaster::pixel`], telling `rec` of every ray past the centre's.
    pub fn pixel_told<R: Record>(
        &self,
        (row, column): (usize, usize),
        (centre, hit): (Ray, Option<Hit>),
        rec: &mut R,
        stats: &mut Stats,
    ) -> V3<f64> {
        let p = self.prepared;
        let mut rng = pixel_rng(p.lighting.settings.seed, row * p.width + column);
        if !self.on.antialiasing {
            return match hit {
                Some(hit) => {
                    self.radiance(hit, centre, (RayKind::Primary, 0), (&mut rng, rec), stats)
                }
                None => [0.0; 3],
            };
        }
        if let Some(hit) = hit {
            self.surface_at(&hit, &centre, stats);
        }
        let rays = self.sample_rays((row, column), &mut rng);
        let hits: Vec<Option<Hit>> = rays.iter().map(|ray| self.cast(*ray, stats)).collect();
        self.mean_of_samples((&rays, &hits), (&mut rng, rec), stats)
    }

    /// The pixels of rows `first..` with antialiasing, as [`SecondaryCaster::pixel`] colours them
    /// from their centres' rays and hits (`primary`), but with the sample rays of neighbouring
    /// pixels cast together ([`cast::nearest_hits_of_each`]: the same hits as one at a time).
    /// Each pixel's generator makes its sample rays, then shades what they met, as before.
    fn sample_rows(
        &self,
        first: usize,
        primary: &[(Ray, Option<Hit>)],
        pixels: &mut [[f32; 3]],
        stats: &mut Stats,
    ) {
        let p = self.prepared;
        let mut generators = Vec::with_capacity(primary.len());
        let mut rays = Vec::new();
        for (at, (centre, hit)) in primary.iter().enumerate() {
            let (row, column) = (first + at / p.width, at % p.width);
            let mut rng = pixel_rng(p.lighting.settings.seed, row * p.width + column);
            if let Some(hit) = hit {
                self.surface_at(hit, centre, stats);
            }
            rays.extend(self.sample_rays((row, column), &mut rng));
            generators.push(rng);
        }
        let hits = secondary_work(stats, |s| cast::nearest_hits_of_each(p, &rays, s));
        // At least one sample a pixel (k ≥ 1), and no pixel at all in an empty band.
        let per_pixel = (rays.len() / primary.len().max(1)).max(1);
        let met: Vec<(Ray, Option<Hit>)> = rays.iter().copied().zip(hits.iter().copied()).collect();
        let ahead = self.cast_ahead(&met, stats);
        let each = rays.chunks(per_pixel).zip(hits.chunks(per_pixel));
        for ((pixel, mut rng), samples) in pixels.iter_mut().zip(generators).zip(each) {
            let colour = self.mean_of_samples(samples, (&mut rng, &mut ahead.found()), stats);
            *pixel = colour.map(|c| c as f32);
        }
    }

    /// A band's mirror and glass rays, cast together ahead of the shading that asks for them,
    /// bounce by bounce: `met` holds what the pixels' rays met (their centres', or their
    /// samples'); each hit's onward rays are those [`SecondaryCaster::radiance`] traces from it
    /// ([`SecondaryCaster::onward`]), so each ray cast ahead is asked for once. Their hits are
    /// those of [`cast::nearest_hit_between`] ([`cast::nearest_hits_of_each`]): the image is the
    /// same as with each ray cast when asked for.
    fn cast_ahead(&self, met: &[(Ray, Option<Hit>)], stats: &mut Stats) -> CastAhead {
        let mut ahead = CastAhead::default();
        let p = self.prepared;
        let mut depth = 0;
        let mut rays = self.onward_rays(met, depth);
        while !rays.is_empty() {
            let hits = secondary_work(stats, |s| cast::nearest_hits_of_each(p, &rays, s));
            let bounce: Vec<(Ray, Option<Hit>)> = rays.into_iter().zip(hits).collect();
            ahead
                .hits
                .extend(bounce.iter().map(|(ray, hit)| (ray_bits(ray), *hit)));
            depth += 1;
            rays = self.onward_rays(&bounce, depth);
        }
        ahead
    }

    /// The rays the mirror and glass hits of `met` send on (rays that took `depth` bounces): the
    /// glass's refracted rays (and those reflected inside it) in order, then the reflected rays in
    /// order, so that a packet's rays go much the same way.
    fn onward_rays(&self, met: &[(Ray, Option<Hit>)], depth: u32) -> Vec<Ray> {
        let (mut onward, mut reflections) = (Vec::new(), Vec::new());
        for (ray, hit) in met {
            // Only a hit that sends rays on needs its surface worked out here.
            let Some(hit) = hit.filter(|hit| self.sending_on(hit.object, depth).is_some()) else {
                continue;
            };
            // The shading's counters are the render's, counted where the hit is shaded.
            let surface = self.surface_at(&hit, ray, &mut Stats::default());
            let spot = Spot::of(&surface, ray, hit.t);
            match self.onward(hit.object, (&ray.dir, depth), &surface, &spot) {
                Onward::Stops => {}
                Onward::Mirror { reflected, .. } => reflections.push(reflected),
                Onward::Inside { reflected } => onward.push(reflected),
                Onward::Glass {
                    refracted,
                    reflected,
                    ..
                } => {
                    onward.push(refracted);
                    reflections.extend(reflected);
                }
            }
        }
        onward.append(&mut reflections);
        onward
    }

    /// A pixel's k×k stratified sample rays, drawn from its generator.
    fn sample_rays(&self, (row, column): (usize, usize), rng: &mut Pcg32) -> Vec<Ray> {
        let samples = stratified(self.prepared.lighting.settings.samples_per_side, rng);
        // Cell (x, y) of the pixel around its centre.
        let ray_in =
            |(x, y): &(f64, f64)| self.ray_at(row as f64 + y - 0.5, column as f64 + x - 0.5);
        samples.iter().map(ray_in).collect()
    }

    /// The mean colour of a pixel's sample rays, given what each met.
    fn mean_of_samples<R: Record>(
        &self,
        (rays, hits): (&[Ray], &[Option<Hit>]),
        (rng, rec): (&mut Pcg32, &mut R),
        stats: &mut Stats,
    ) -> V3<f64> {
        let mut sum = [0.0; 3];
        for (ray, hit) in rays.iter().zip(hits) {
            let kind = (RayKind::Sample, 0);
            let c = self.colour_met(*ray, *hit, kind, (&mut *rng, &mut *rec), stats);
            sum = std::array::from_fn(|k| sum[k] + c[k]);
        }
        sum.map(|c| c / rays.len() as f64)
    }

    /// The surface a ray hit, with its shading work counted in `stats`.
    fn surface_at(&self, hit: &Hit, ray: &Ray, stats: &mut Stats) -> Surface {
        let object = &self.prepared.objects[hit.object];
        let inverse_length = 1.0 / dot(&ray.dir, &ray.dir).sqrt();
        self.shader
            .surface(object, hit, &ray.dir, inverse_length, stats)
    }

    /// The ray through the fractional pixel position (row, column), centres at whole numbers.
    pub(super) fn ray_at(&self, row: f64, column: f64) -> Ray {
        let p = self.prepared;
        camera_ray_at(
            &p.camera,
            self.basis.as_ref(),
            (p.width, p.height),
            row,
            column,
        )
    }

    /// The colour a secondary ray of `kind` brings back (black when it escapes), counted by kind.
    fn trace<R: Record>(
        &self,
        ray: Ray,
        (kind, depth): (RayKind, u32),
        (rng, rec): (&mut Pcg32, &mut R),
        stats: &mut Stats,
    ) -> V3<f64> {
        let hit = match rec.cast_ahead(&ray) {
            Some(hit) => hit,
            None => self.cast(ray, stats),
        };
        self.colour_met(ray, hit, (kind, depth), (rng, rec), stats)
    }

    /// The nearest hit of a secondary ray, its work counted as the effects'.
    fn cast(&self, ray: Ray, stats: &mut Stats) -> Option<Hit> {
        secondary_work(stats, |s| {
            cast::nearest_hit_between(self.prepared, ray, (0.0, f64::INFINITY), s)
        })
    }

    /// [`SecondaryCaster::trace`] given what the ray met: the colour it brings back.
    fn colour_met<R: Record>(
        &self,
        ray: Ray,
        hit: Option<Hit>,
        (kind, depth): (RayKind, u32),
        (rng, rec): (&mut Pcg32, &mut R),
        stats: &mut Stats,
    ) -> V3<f64> {
        stats.secondary.count(kind);
        rec.start(kind, depth, ray);
        rec.met(hit);
        let colour = match hit {
            Some(hit) => {
                stats.secondary.hits += 1;
                self.radiance(hit, ray, (kind, depth), (rng, &mut *rec), stats)
            }
            None => [0.0; 3],
        };
        rec.end(colour);
        colour
    }

    /// The colour seen along `ray` at `hit`: the surface lit, then its material's rays.
    /// `(kind, depth)`: the ray's kind and how many bounces led to it.
    pub(super) fn radiance<R: Record>(
        &self,
        hit: Hit,
        ray: Ray,
        (kind, depth): (RayKind, u32),
        (rng, rec): (&mut Pcg32, &mut R),
        stats: &mut Stats,
    ) -> V3<f64> {
        // The primary ray's shading work counts as ray casting's; the rest as the effects'.
        let surface = if kind == RayKind::Primary {
            self.surface_at(&hit, &ray, stats)
        } else {
            self.surface_at(&hit, &ray, &mut Stats::default())
        };
        let spot = Spot::of(&surface, &ray, hit.t);
        let local = self.local(&surface, &spot, (&mut *rng, &mut *rec), stats);
        let lit = (&surface, &spot, local);
        self.with_onward((hit, ray), depth, lit, (rng, rec), stats)
    }

    /// [`SecondaryCaster::radiance`] given the surface `ray` met at `hit` after `depth` bounces,
    /// where, and its own colour (`local`, lit): that colour faded, mixed with what its material's
    /// rays bring back.
    fn with_onward<R: Record>(
        &self,
        (hit, ray): (Hit, Ray),
        depth: u32,
        (surface, spot, local): (&Surface, &Spot, V3<f64>),
        (rng, rec): (&mut Pcg32, &mut R),
        stats: &mut Stats,
    ) -> V3<f64> {
        let local = local.map(|c| c * surface.fade);
        let kind_on = |kind| (kind, depth + 1);
        match self.onward(hit.object, (&ray.dir, depth), surface, spot) {
            Onward::Stops => local,
            Onward::Mirror {
                reflected,
                reflectance,
            } => {
                let kind = kind_on(RayKind::Reflection);
                let mirrored = self.trace(reflected, kind, (rng, rec), stats);
                mix(&local, &mirrored, reflectance)
            }
            Onward::Inside { reflected } => {
                let kind = kind_on(RayKind::Refraction);
                self.trace(reflected, kind, (rng, rec), stats)
            }
            Onward::Glass {
                refracted,
                reflected,
                fresnel,
            } => {
                let kind = kind_on(RayKind::Refraction);
                let through = self.trace(refracted, kind, (&mut *rng, &mut *rec), stats);
                let mirrored = match reflected {
                    Some(ray) => self.trace(ray, kind_on(RayKind::Reflection), (rng, rec), stats),
                    // Without `reflections` the surface's own colour stands in for the reflection.
                    None => local,
                };
                mix(&through, &mirrored, fresnel)
            }
        }
    }

    /// The rays the material of `object` sends on from a hit of a ray along `dir` that took
    /// `depth` bounces: a mirror's reflected ray; glass's refracted ray and reflected one (mixed by
    /// Schlick's Fresnel term), or past the critical angle the ray reflected wholly, inside the
    /// glass. None where the material's effect is off or the depth limit is reached.
    fn onward(
        &self,
        object: usize,
        (dir, depth): (&V3<f64>, u32),
        surface: &Surface,
        spot: &Spot,
    ) -> Onward {
        let mirrored = |d: &V3<f64>| {
            let reflected = reflect(d, &spot.front);
            Ray::new(self.off_surface(spot, &reflected), reflected)
        };
        match self.sending_on(object, depth) {
            Some(Material::Mirror { reflectance }) => Onward::Mirror {
                reflected: mirrored(dir),
                reflectance,
            },
            Some(Material::Glass { ior }) => {
                let entering = dot(&surface.normal, dir) < 0.0;
                let (from_eta, to_eta) = if entering { (1.0, ior) } else { (ior, 1.0) };
                let d = unit(*dir);
                let Some(through) = refract(&d, &spot.front, from_eta, to_eta) else {
                    return Onward::Inside {
                        reflected: mirrored(&d),
                    };
                };
                Onward::Glass {
                    refracted: Ray::new(self.off_surface(spot, &through), through),
                    reflected: self.on.reflections.then(|| mirrored(&d)),
                    fresnel: schlick(-dot(&d, &spot.front), from_eta, to_eta),
                }
            }
            _ => Onward::Stops,
        }
    }

    /// The material of `object` where a hit on it after `depth` bounces sends rays on: a mirror
    /// with `reflections`, glass with `refraction`, below the depth limit.
    fn sending_on(&self, object: usize, depth: u32) -> Option<Material> {
        if depth >= self.prepared.lighting.settings.max_depth {
            return None;
        }
        let material = self.prepared.lighting.material(object);
        match material {
            Material::Mirror { .. } if self.on.reflections => Some(material),
            Material::Glass { .. } if self.on.refraction => Some(material),
            _ => None,
        }
    }

    /// The surface's own colour: lit by the lights (with shadow rays and ambient occlusion when
    /// declared), or shaded by the facing ratio without lights.
    fn local<R: Record>(
        &self,
        surface: &Surface,
        spot: &Spot,
        (rng, rec): (&mut Pcg32, &mut R),
        stats: &mut Stats,
    ) -> V3<f64> {
        let lighting = &self.prepared.lighting;
        let occlusion_rays = lighting.settings.occlusion_rays as usize;
        // A hit's occlusion rays and its lights' shadow rays in one packet when they fit: they
        // leave the same point, so they walk the index and the meshes near it once.
        let together = self.on.occlusion
            && self.on.shadows
            && !lighting.lights.is_empty()
            && occlusion_rays > 0
            && occlusion_rays + lighting.lights.len() <= cast::TOGETHER;
        // Every light's shadow ray, made before the occlusion rays are cast with them.
        let all_lights = together.then(|| self.shadow_packet(spot, &lighting.lights, stats));
        let (open, shadows_blocked) = match &all_lights {
            Some(shadows) => {
                let (open, blocked) =
                    self.openness_with_shadows(spot, shadows, (rng, &mut *rec), stats);
                (open, blocked)
            }
            None if self.on.occlusion => (self.openness(spot, (rng, &mut *rec), stats), 0),
            None => (1.0, 0),
        };
        if lighting.lights.is_empty() {
            let ratio = surface.facing.map_or(1.0, |f| f.max(0.0));
            return surface.base.map(|c| c * ratio * open);
        }
        let point = &spot.point;
        self.lit(surface, open, |light| match &all_lights {
            // Every light's shadow ray was cast with the occlusion rays.
            Some(shadows) => {
                let found = (shadows.view(), shadows_blocked);
                self.add_light(light, (0, &lighting.lights), point, found, rec);
            }
            // Sixteen lights at a time: their shadow rays are cast together (they share their
            // origin, or nearly, and go to lights near one another, so they meet the same boxes).
            None => {
                for (chunk, sources) in lighting.lights.chunks(cast::TOGETHER).enumerate() {
                    let shadows = self.shadow_packet(spot, sources, stats);
                    let tested = (&shadows.rays, shadows.tested);
                    let kind = RayKind::Shadow;
                    let blocked = self.blocked_together(tested, &shadows.t_max, kind, rec, stats);
                    let first = chunk * cast::TOGETHER;
                    let found = (shadows.view(), blocked);
                    self.add_light(light, (first, sources), point, found, rec);
                }
            }
        })
    }

    /// A lit surface's own colour: its colour times the light, which is the ambient term (times
    /// `open`, the share of occlusion rays that escaped) plus what `add_lights` adds.
    #[inline(always)]
    fn lit(&self, surface: &Surface, open: f64, add_lights: impl FnOnce(&mut V3<f64>)) -> V3<f64> {
        let mut light = [self.prepared.lighting.settings.ambient * open; 3];
        add_lights(&mut light);
        std::array::from_fn(|k| surface.base[k] * light[k])
    }

    /// [`SecondaryCaster::openness`] with every light's shadow ray (`shadows`) cast in the same
    /// packet, the occlusion rays in lanes from 0 and the shadow rays after them: the share of
    /// occlusion rays that escape, and the set of shadow rays blocked. Each ray's answer is the
    /// same as in a packet of its own kind ([`cast::any_hits`] answers each ray as alone), told to
    /// `rec` as two packets, in the order they were cast before.
    #[inline(always)]
    fn openness_with_shadows<R: Record>(
        &self,
        spot: &Spot,
        shadows: &ShadowPacket,
        (rng, rec): (&mut Pcg32, &mut R),
        stats: &mut Stats,
    ) -> (f64, u32) {
        let n = self.prepared.lighting.settings.occlusion_rays as usize;
        let occlusion = self.occlusion_packet(spot, n, rng);
        let reach = [self.reach(); cast::TOGETHER];
        let (mut rays, mut t_max) = (occlusion, reach);
        rays[n..].copy_from_slice(&shadows.rays[..cast::TOGETHER - n]);
        t_max[n..].copy_from_slice(&shadows.t_max[..cast::TOGETHER - n]);
        let occluding = (1u32 << n) - 1;
        let kind = RayKind::Occlusion;
        self.tell_any_hits((&occlusion, occluding), &reach, kind, rec, stats);
        let blocked = self.cast_any_hits((&rays, occluding | shadows.tested << n), &t_max, stats);
        let open = self.share_escaping((blocked & occluding).count_ones(), rec);
        let (shadow_rays, kind) = ((&shadows.rays, shadows.tested), RayKind::Shadow);
        self.tell_any_hits(shadow_rays, &shadows.t_max, kind, rec, stats);
        (open, blocked >> n)
    }

    /// The shadow rays of up to sixteen lights from `spot`: each light's cosine (0: the surface
    /// faces away), and the ray and its length where the light is tested.
    #[inline(always)]
    fn shadow_packet(&self, spot: &Spot, sources: &[Light], stats: &mut Stats) -> ShadowPacket {
        let mut packet = ShadowPacket {
            cosines: [0.0; cast::TOGETHER],
            rays: [UNUSED_LANE; cast::TOGETHER],
            t_max: [0.0; cast::TOGETHER],
            tested: 0,
        };
        let lanes = ShadowLanes {
            cosines: &mut packet.cosines,
            rays: &mut packet.rays,
            t_max: &mut packet.t_max,
        };
        packet.tested = self.shadow_rays_into(spot, sources, lanes, stats);
        packet
    }

    /// Writes light i's cosine at `spot` (0: the surface faces away) and, where it is tested, its
    /// shadow ray and the ray's length in lane i of `lanes`: the set of lights tested.
    #[inline(always)]
    fn shadow_rays_into(
        &self,
        spot: &Spot,
        sources: &[Light],
        lanes: ShadowLanes<'_>,
        stats: &mut Stats,
    ) -> u32 {
        let (point, front) = (&spot.point, &spot.front);
        let mut tested = 0;
        for (i, source) in sources.iter().enumerate() {
            stats.secondary.light_evaluations += 1;
            let incoming = incoming(source, point);
            let cosine = lambert(front, &incoming.toward);
            lanes.cosines[i] = cosine;
            if cosine == 0.0 {
                continue;
            }
            if self.on.shadows {
                let from = self.off_surface(spot, &incoming.toward);
                lanes.rays[i] = Ray::new(from, incoming.toward_from(point, &from));
                lanes.t_max[i] = incoming.t_max;
                tested |= 1 << i;
            }
        }
        tested
    }

    /// Adds to `light` what `sources` (lights `first..` of the scene) bring to `point`, given
    /// their shadow rays and which of them were blocked (a bit set), telling `rec` of each.
    #[inline(always)]
    fn add_light<R: Record>(
        &self,
        light: &mut V3<f64>,
        (first, sources): (usize, &[Light]),
        point: &V3<f64>,
        (shadows, blocked): (ShadowRays<'_>, u32),
        rec: &mut R,
    ) {
        for (i, (source, &cosine)) in sources.iter().zip(shadows.cosines).enumerate() {
            let index = first + i;
            if cosine == 0.0 {
                rec.light(index, LightTest::FacesAway);
                continue;
            }
            let (ray, t_max) = (shadows.rays[i], shadows.t_max[i]);
            match (shadows.tested >> i & 1 != 0, blocked >> i & 1 != 0) {
                (false, _) => rec.light(index, LightTest::Untested),
                (true, true) => {
                    rec.light(index, LightTest::Blocked(ray, t_max));
                    continue;
                }
                (true, false) => rec.light(index, LightTest::Lit(ray, t_max)),
            }
            // The light worked out again (the same numbers), which costs less than keeping it.
            for (l, e) in light.iter_mut().zip(incoming(source, point).irradiance) {
                *l += e * cosine;
            }
        }
    }

    /// How far an occlusion ray looks.
    fn reach(&self) -> f64 {
        let settings = &self.prepared.lighting.settings;
        settings.occlusion_distance.unwrap_or(f64::INFINITY)
    }

    /// `n` (at most sixteen) cosine-weighted occlusion rays over the hemisphere about the shading
    /// normal, drawn from `rng`, in lanes from 0. They leave from the normal's side.
    fn occlusion_packet(&self, spot: &Spot, n: usize, rng: &mut Pcg32) -> [Ray; cast::TOGETHER] {
        let from = self.off_surface(spot, &spot.front);
        let mut rays = [UNUSED_LANE; cast::TOGETHER];
        for ray in &mut rays[..n] {
            *ray = Ray::new(from, cosine_hemisphere(&spot.front, rng));
        }
        rays
    }

    /// The share of `occlusion_rays` cosine-weighted rays over the hemisphere that escape (within
    /// `occlusion_distance`): 1 for an open plane.
    fn openness<R: Record>(
        &self,
        spot: &Spot,
        (rng, rec): (&mut Pcg32, &mut R),
        stats: &mut Stats,
    ) -> f64 {
        let cast = self.prepared.lighting.settings.occlusion_rays;
        let t_max = [self.reach(); cast::TOGETHER];
        let mut blocked = 0;
        // Cast together, up to sixteen at a time (they share their origin).
        let mut left = cast as usize;
        while left > 0 {
            let n = left.min(cast::TOGETHER);
            left -= n;
            let rays = self.occlusion_packet(spot, n, rng);
            let tested = (&rays, (1u32 << n) - 1);
            let found = self.blocked_together(tested, &t_max, RayKind::Occlusion, rec, stats);
            blocked += found.count_ones();
        }
        self.share_escaping(blocked, rec)
    }

    /// The share of the occlusion rays that escape, `blocked` of them not (told to `rec`).
    fn share_escaping<R: Record>(&self, blocked: u32, rec: &mut R) -> f64 {
        let cast = self.prepared.lighting.settings.occlusion_rays;
        rec.occlusion(cast, blocked);
        f64::from(cast - blocked) / f64::from(cast)
    }

    /// Which of the shadow or occlusion rays of `taking` (a bit set) meet something within
    /// (0, t_max[r]): the set of those blocked. Cast together ([`cast::any_hits`]).
    fn blocked_together<R: Record>(
        &self,
        (rays, taking): (&[Ray; cast::TOGETHER], u32),
        t_max: &[f64; cast::TOGETHER],
        kind: RayKind,
        rec: &mut R,
        stats: &mut Stats,
    ) -> u32 {
        if taking == 0 {
            return 0;
        }
        self.tell_any_hits((rays, taking), t_max, kind, rec, stats);
        self.cast_any_hits((rays, taking), t_max, stats)
    }

    /// Casts the shadow or occlusion rays of `taking` together ([`cast::any_hits`]), their work
    /// counted as the effects'; the set of those blocked.
    fn cast_any_hits(
        &self,
        (rays, taking): (&[Ray; cast::TOGETHER], u32),
        t_max: &[f64; cast::TOGETHER],
        stats: &mut Stats,
    ) -> u32 {
        let blocked = secondary_work(stats, |s| {
            cast::any_hits(self.prepared, (rays, taking), t_max, s)
        });
        stats.secondary.blocked += u64::from(blocked.count_ones());
        blocked
    }

    /// Counts the rays of `taking` as cast and tells `rec` of them, as a packet of `kind` (none
    /// when no ray takes part).
    fn tell_any_hits<R: Record>(
        &self,
        (rays, taking): (&[Ray; cast::TOGETHER], u32),
        t_max: &[f64; cast::TOGETHER],
        kind: RayKind,
        rec: &mut R,
        stats: &mut Stats,
    ) {
        if taking == 0 {
            return;
        }
        rec.any_hits_together();
        tell_queries((rays, taking), t_max, kind, rec, stats);
    }

    /// The origin of a secondary ray going along `toward`: the hit point moved `offset` along the
    /// face's normal, to the side of the face the ray goes to, so the ray cannot meet the face it
    /// leaves (along an interpolated normal it could: the shadow acne the app shows as a bug). The
    /// point itself under the shadow-acne bug.
    fn off_surface(&self, spot: &Spot, toward: &V3<f64>) -> V3<f64> {
        if self.prepared.bug == Some(Bug::ShadowAcne) {
            return spot.point;
        }
        let side = if dot(&spot.face, toward) >= 0.0 {
            1.0
        } else {
            -1.0
        };
        let offset = self.prepared.lighting.settings.offset * side;
        std::array::from_fn(|k| spot.point[k] + offset * spot.face[k])
    }
}

/// Counts the rays of `taking` as cast and tells `rec` of each, a query of `kind`.
fn tell_queries<R: Record>(
    (rays, taking): (&[Ray; cast::TOGETHER], u32),
    t_max: &[f64; cast::TOGETHER],
    kind: RayKind,
    rec: &mut R,
    stats: &mut Stats,
) {
    for r in cast::bits(taking) {
        stats.secondary.count(kind);
        rec.any_hit_query(kind, rays[r], t_max[r]);
    }
}

/// What a packet's lanes hold before their rays are written: zeros, which cost less to write than
/// a ray; a lane no ray takes is never read ([`cast::any_hits`]).
const UNUSED_LANE: Ray = Ray::new([0.0; 3], [0.0; 3]);

/// The shadow rays of up to sixteen lights from one hit.
struct ShadowPacket {
    /// Each light's cosine at the hit (0: the surface faces away).
    cosines: [f64; cast::TOGETHER],
    rays: [Ray; cast::TOGETHER],
    t_max: [f64; cast::TOGETHER],
    /// The lights whose shadow rays are cast (a bit set).
    tested: u32,
}

impl ShadowPacket {
    fn view(&self) -> ShadowRays<'_> {
        ShadowRays {
            cosines: &self.cosines,
            rays: &self.rays,
            t_max: &self.t_max,
            tested: self.tested,
        }
    }
}

/// A hit's lights' cosines, shadow rays and the rays' lengths (light i's in lane i), and which
/// lights were tested (a bit set): a [`ShadowPacket`], or a hit's lanes of a packet cast ahead.
#[derive(Clone, Copy)]
struct ShadowRays<'a> {
    cosines: &'a [f64],
    rays: &'a [Ray],
    t_max: &'a [f64],
    tested: u32,
}

/// Where [`SecondaryCaster::shadow_rays_into`] writes a hit's lights' cosines and shadow rays.
struct ShadowLanes<'a> {
    cosines: &'a mut [f64],
    rays: &'a mut [Ray],
    t_max: &'a mut [f64],
}

/// Where secondary rays leave a hit.
struct Spot {
    /// The hit point.
    point: V3<f64>,
    /// The shading normal, turned to the side the ray came from.
    front: V3<f64>,
    /// The flat face's unit normal, as the geometry orients it (see [`Surface::face`]).
    face: V3<f64>,
}

/// A band's mirror and glass rays and their hits, cast ahead ([`SecondaryCaster::cast_ahead`]),
/// by the rays' bits.
#[derive(Default)]
struct CastAhead {
    hits: HitsByRay,
}

/// Hits by their rays' bits.
type HitsByRay = HashMap<RayBits, Option<Hit>, BuildHasherDefault<Mixed>>;

/// A ray's numbers as bits: a ray the same to the bit has the same hit.
#[derive(PartialEq, Eq)]
struct RayBits([u64; 6]);

fn ray_bits(ray: &Ray) -> RayBits {
    let [o, d] = [ray.origin, ray.dir].map(|v| v.map(f64::to_bits));
    RayBits([o[0], o[1], o[2], d[0], d[1], d[2]])
}

impl Hash for RayBits {
    /// One word for the six, multiplied and rotated in (a map's hasher by default, SipHash, took
    /// 3% of the Cornell box's instructions for these few lookups).
    fn hash<H: Hasher>(&self, state: &mut H) {
        let mixed = self.0.iter().fold(0u64, |h, word| {
            (h.rotate_left(23) ^ word).wrapping_mul(0x9e37_79b9_7f4a_7c15)
        });
        state.write_u64(mixed);
    }
}

/// The hasher of [`RayBits`]: the one word it is given, its high bits moved down (the map picks
/// a bucket by the low bits, and the multiply mixes upward).
#[derive(Default)]
struct Mixed(u64);

impl Hasher for Mixed {
    fn finish(&self) -> u64 {
        self.0 ^ (self.0 >> 32)
    }

    fn write(&mut self, bytes: &[u8]) {
        for byte in bytes {
            self.0 = (self.0.rotate_left(8) ^ u64::from(*byte)).wrapping_mul(0x9e37_79b9_7f4a_7c15);
        }
    }

    fn write_u64(&mut self, word: u64) {
        self.0 = word;
    }
}

impl CastAhead {
    /// The hits cast ahead, for the shading to find ([`Record::cast_ahead`]).
    fn found(&self) -> FoundAhead<'_> {
        FoundAhead(&self.hits)
    }
}

/// The hits of rays cast ahead, as a band's shading asks for them; records nothing.
struct FoundAhead<'a>(&'a HitsByRay);

impl Record for FoundAhead<'_> {
    fn cast_ahead(&mut self, ray: &Ray) -> Option<Option<Hit>> {
        self.0.get(&ray_bits(ray)).copied()
    }
}

/// What a hit's material sends on ([`SecondaryCaster::onward`]).
enum Onward {
    /// Neither mirror nor glass, its effect off, or the depth limit reached.
    Stops,
    /// A mirror's reflected ray, mixed with the surface's own colour by `reflectance`.
    Mirror { reflected: Ray, reflectance: f64 },
    /// Glass past the critical angle: the ray reflected wholly, inside the glass (a refraction
    /// ray).
    Inside { reflected: Ray },
    /// Glass: the refracted ray, mixed with the reflected one (`None` without `reflections`: the
    /// surface's own colour stands in) by Schlick's Fresnel term.
    Glass {
        refracted: Ray,
        reflected: Option<Ray>,
        fresnel: f64,
    },
}

impl Spot {
    /// Where a ray meets `surface` at `t`.
    fn of(surface: &Surface, ray: &Ray, t: f64) -> Spot {
        Spot {
            point: ray.at(t),
            // The normal on the side the ray came from.
            front: if dot(&surface.normal, &ray.dir) > 0.0 {
                surface.normal.map(|c| -c)
            } else {
                surface.normal
            },
            face: surface.face,
        }
    }
}

/// (1 − w)·a + w·b.
fn mix(a: &V3<f64>, b: &V3<f64>, w: f64) -> V3<f64> {
    std::array::from_fn(|k| (1.0 - w) * a[k] + w * b[k])
}

/// Runs a secondary ray's cast on its own counters and adds its work to `stats.secondary`.
fn secondary_work<T>(stats: &mut Stats, cast: impl FnOnce(&mut Stats) -> T) -> T {
    let mut own = Stats::default();
    let answer = cast(&mut own);
    let s = &mut stats.secondary;
    s.tests += own.triangle_tests + own.parallelogram_tests;
    s.box_tests += own.box_tests;
    s.transforms += own.transforms;
    answer
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::ray_kinds::Secondary;

    /// A band's pixels, with its first mirror and glass rays cast ahead together (and its samples),
    /// are the same to the bit as each pixel shaded alone, every ray cast one at a time: in every
    /// shipped scene, with and without antialiasing, with and without the shadow-acne bug (whose
    /// rays leave from the surface itself).
    #[test]
    fn a_band_renders_each_pixel_as_alone() {
        let (mut mirrors_and_glass, mut shadows_ahead) = (0, 0);
        // Antialiasing, ambient occlusion, the bug: without the two (and with shadows), a band's
        // first hits' shadow rays are cast ahead, several hits' together where a scene has one
        // light or two (the one-light scene; the reflections scene, its mirror's hits casting
        // theirs when asked).
        let variants = [
            (true, true, None),
            (false, true, None),
            (true, true, Some(Bug::ShadowAcne)),
            (false, false, None),
            (false, false, Some(Bug::ShadowAcne)),
        ];
        for (name, shipped) in crate::render::shipped_scenes(40, 30) {
            for (antialiasing, occlusion, bug) in variants {
                let mut prepared = shipped.clone();
                prepared.bug = bug;
                if !antialiasing {
                    prepared.effects.retain(|e| *e != Effect::Antialiasing);
                }
                if !occlusion {
                    prepared.effects.retain(|e| *e != Effect::AmbientOcclusion);
                    if !prepared.effects.contains(&Effect::Shadows) {
                        prepared.effects.push(Effect::Shadows);
                    }
                }
                if !applies(&prepared) {
                    continue;
                }
                let caster = SecondaryCaster::new(&prepared);
                let width = prepared.width;
                let mut pixels = vec![[0.0f32; 3]; width * prepared.height];
                let mut covered = vec![false; pixels.len()];
                let stats = caster.render_rows(0, &mut pixels, &mut covered);
                mirrors_and_glass += stats.rays_of(RayKind::Reflection);
                mirrors_and_glass += stats.rays_of(RayKind::Refraction);
                if caster.shadows_go_ahead() {
                    shadows_ahead += stats.rays_of(RayKind::Shadow);
                }
                let mut each_alone = Stats::default();
                for (at, shown) in pixels.iter().enumerate() {
                    let (row, column) = (at / width, at % width);
                    let centre = prepared.ray(row, column);
                    let hit = cast::nearest_hit(&prepared, centre, &mut Stats::default());
                    let alone = caster.pixel((row, column), centre, hit, &mut each_alone);
                    let alone = alone.map(|c| (c as f32).to_bits());
                    assert_eq!(
                        shown.map(f32::to_bits),
                        alone,
                        "{name}, antialiasing {antialiasing}, occlusion {occlusion}, {bug:?}: \
                         pixel ({row}, {column})"
                    );
                }
                // The same rays by kind, blocked as often, the same lights evaluated: only the
                // work of casting them (tests, box tests) may differ.
                let told = |s: &Stats| Secondary {
                    tests: 0,
                    box_tests: 0,
                    transforms: 0,
                    ..s.secondary
                };
                assert_eq!(
                    told(&stats),
                    told(&each_alone),
                    "{name}, {antialiasing}, {bug:?}"
                );
            }
        }
        assert!(
            mirrors_and_glass > 1000,
            "{mirrors_and_glass} mirror and glass rays"
        );
        assert!(
            shadows_ahead > 1000,
            "{shadows_ahead} shadow rays cast ahead"
        );
    }

    /// Every mirror and glass ray a pixel's shading asks for was cast ahead, at every bounce
    /// (a ray the band's cast missed would be cast again alone: the same image, the time lost).
    /// At 100x75 the glass sphere of the refraction scene reflects some rays wholly inside.
    #[test]
    fn every_mirror_and_glass_ray_is_found_ahead() {
        /// Asks the rays cast ahead, counting those not found.
        struct Asking<'a> {
            found: FoundAhead<'a>,
            asked: u64,
            missed: u64,
        }
        impl Record for Asking<'_> {
            fn cast_ahead(&mut self, ray: &Ray) -> Option<Option<Hit>> {
                let found = self.found.cast_ahead(ray);
                self.asked += 1;
                self.missed += u64::from(found.is_none());
                found
            }
        }
        let mut asked = 0;
        for (name, mut prepared) in crate::render::shipped_scenes(100, 75) {
            prepared.effects.retain(|e| *e != Effect::Antialiasing);
            if !applies(&prepared) {
                continue;
            }
            let caster = SecondaryCaster::new(&prepared);
            let width = prepared.width;
            let met: Vec<(Ray, Option<Hit>)> = (0..width * prepared.height)
                .map(|at| {
                    let ray = prepared.ray(at / width, at % width);
                    (
                        ray,
                        cast::nearest_hit(&prepared, ray, &mut Stats::default()),
                    )
                })
                .collect();
            let ahead = caster.cast_ahead(&met, &mut Stats::default());
            let mut asking = Asking {
                found: ahead.found(),
                asked: 0,
                missed: 0,
            };
            for (at, met) in met.iter().enumerate() {
                let place = (at / width, at % width);
                caster.pixel_told(place, *met, &mut asking, &mut Stats::default());
            }
            assert_eq!(asking.missed, 0, "{name}: of {} asked", asking.asked);
            asked += asking.asked;
        }
        assert!(asked > 1000, "{asked} mirror and glass rays asked for");
    }

    /// A band of no rows renders nothing and casts nothing, also where antialiasing's samples are
    /// cast together (the Cornell box, the antialiasing scene).
    #[test]
    fn an_empty_band_renders_nothing() {
        for (name, prepared) in crate::render::shipped_scenes(24, 16) {
            let stats = SecondaryCaster::new(&prepared).render_rows(0, &mut [], &mut []);
            assert_eq!(stats.rays, 0, "{name}");
            assert_eq!(stats.secondary, Default::default(), "{name}");
        }
    }
}
