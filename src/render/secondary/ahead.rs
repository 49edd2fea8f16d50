//! A band's first hits shaded a few neighbours at a time, their shadow rays cast together first.
//! Shaded one at a time, a scene with one light cast each hit's shadow ray alone: a packet of one
//! ray, which a packet walk cannot share. Neighbouring hits' shadow rays leave nearby points for
//! the same lights, so sixteen lanes of them walk the index together (the one-light scene's 22 922
//! shadow rays, one thread: 1.5–1.6 ms a cast alone, 0.4–0.6 ms so, in the ray-kind loop). Each
//! ray's answer is the same as alone ([`cast::any_hits`]), and each pixel is shaded as
//! [`SecondaryCaster::pixel_told`] shades it, so the image is the same to the bit.

use std::ops::Range;

use rand_pcg::Pcg32;

use super::{
    Record, SecondaryCaster, ShadowLanes, ShadowRays, Spot, Surface, UNUSED_LANE, secondary_work,
    tell_queries,
};
use crate::math::linalg::V3;
use crate::render::shading::sampling::pixel_rng;
use crate::render::{Hit, Ray, Stats, cast, ray_kinds::RayKind};

/// A pixel's centre ray and what it met.
type Met = (Ray, Option<Hit>);

/// The most lights whose shadow rays are cast ahead: eight hits or more a packet. With one light
/// or two it pays (the one-light scene, and it with a second light: 2.38–2.45 ms a render before,
/// 2.01–2.03 ms after); with four, where a hit's four rays already made a packet, the Cornell box
/// without ambient occlusion and antialiasing took 3–4% longer (38.1–39.4 ms, 38.5–40.3 ms).
const AHEAD_LIGHTS: usize = cast::TOGETHER / 8;

/// A first hit made ready to shade before its shadow rays are cast with its neighbours'.
struct ReadyHit {
    /// The pixel in the band.
    at: usize,
    hit: Hit,
    surface: Surface,
    spot: Spot,
    /// Light i's cosine at the hit (0: the surface faces away).
    cosines: [f64; AHEAD_LIGHTS],
    /// The packet's lane of light 0's ray; light i's is `first + i`.
    first: usize,
    /// The lights tested (a bit set; light i's bit i).
    tested: u32,
}

/// Neighbouring first hits of one row, and their shadow rays in one packet's lanes.
struct Group {
    hits: Vec<ReadyHit>,
    rays: [Ray; cast::TOGETHER],
    t_max: [f64; cast::TOGETHER],
    /// The lanes holding a ray (a bit set).
    taking: u32,
    /// Lanes given to hits so far.
    lanes: usize,
}

impl Group {
    fn new() -> Group {
        Group {
            hits: Vec::with_capacity(cast::TOGETHER),
            rays: [UNUSED_LANE; cast::TOGETHER],
            t_max: [0.0; cast::TOGETHER],
            taking: 0,
            lanes: 0,
        }
    }

    fn clear(&mut self) {
        self.hits.clear();
        self.taking = 0;
        self.lanes = 0;
    }
}

impl SecondaryCaster<'_> {
    /// True when a band's first hits' shadow rays are cast ahead of their shading: shadows on,
    /// no ambient occlusion (which casts a hit's shadow rays with its own), no antialiasing (whose
    /// first hits cast no shadow ray), and few enough lights for eight hits a packet.
    pub(super) fn shadows_go_ahead(&self) -> bool {
        let lights = self.prepared.lighting.lights.len();
        self.on.shadows
            && !self.on.occlusion
            && !self.on.antialiasing
            && (1..=AHEAD_LIGHTS).contains(&lights)
    }

    /// Shades the pixels of a band whose rows start at `first`, given each centre ray and what it
    /// met (`met`), telling `rec` of each pixel ([`Record::pixel`]) and of its rays, and handing
    /// each colour to `put`: the colours of [`SecondaryCaster::pixel_told`]. Where
    /// [`SecondaryCaster::shadows_go_ahead`], neighbouring hits of a row are made ready, their
    /// shadow rays cast in one packet, and then shaded.
    pub(crate) fn shade_band<R: Record>(
        &self,
        first: usize,
        met: &[Met],
        (rec, stats): (&mut R, &mut Stats),
        mut put: impl FnMut(usize, V3<f64>),
    ) {
        let width = self.prepared.width;
        if !self.shadows_go_ahead() {
            for (at, &(ray, hit)) in met.iter().enumerate() {
                rec.pixel(ray);
                let place = (first + at / width, at % width);
                put(at, self.pixel_told(place, (ray, hit), rec, stats));
            }
            return;
        }
        let lights = &self.prepared.lighting.lights;
        let mut group = Group::new();
        let mut shaded = 0;
        for (at, &(ray, hit)) in met.iter().enumerate() {
            let row_starts = at % width == 0;
            if group.lanes + lights.len() > cast::TOGETHER || (row_starts && at > shaded) {
                self.shade_group(&mut group, (first, shaded..at, met), (rec, stats), &mut put);
                shaded = at;
            }
            let Some(hit) = hit else { continue };
            // The first hit's shading work counts as ray casting's, as in `radiance`.
            let surface = self.surface_at(&hit, &ray, stats);
            let spot = Spot::of(&surface, &ray, hit.t);
            let mut ready = ReadyHit {
                at,
                hit,
                surface,
                spot,
                cosines: [0.0; AHEAD_LIGHTS],
                first: group.lanes,
                tested: 0,
            };
            let lanes = group.lanes..group.lanes + lights.len();
            let into = ShadowLanes {
                cosines: &mut ready.cosines,
                rays: &mut group.rays[lanes.clone()],
                t_max: &mut group.t_max[lanes],
            };
            ready.tested = self.shadow_rays_into(&ready.spot, lights, into, stats);
            // A hit facing away from every light keeps no lane.
            if ready.tested != 0 {
                group.taking |= ready.tested << group.lanes;
                group.lanes += lights.len();
            }
            group.hits.push(ready);
        }
        let all = (first, shaded..met.len(), met);
        self.shade_group(&mut group, all, (rec, stats), &mut put);
    }

    /// Casts `group`'s shadow rays together, then shades pixels `pixels` of the band (rows from
    /// `first`), whose hits are the group's, and empties the group.
    fn shade_group<R: Record>(
        &self,
        group: &mut Group,
        (first, pixels, met): (usize, Range<usize>, &[Met]),
        (rec, stats): (&mut R, &mut Stats),
        put: &mut impl FnMut(usize, V3<f64>),
    ) {
        let blocked = if group.taking == 0 {
            0
        } else {
            let together = (&group.rays, group.taking);
            secondary_work(stats, |s| {
                cast::any_hits(self.prepared, together, &group.t_max, s)
            })
        };
        let (width, seed) = (self.prepared.width, self.prepared.lighting.settings.seed);
        let mut hits = group.hits.iter().peekable();
        let mut starts = true;
        for at in pixels {
            let ray = met[at].0;
            rec.pixel(ray);
            // A miss is black, as `pixel_told` colours it without antialiasing.
            let Some(ready) = hits.next_if(|ready| ready.at == at) else {
                put(at, [0.0; 3]);
                continue;
            };
            let (row, column) = (first + at / width, at % width);
            let mut rng = pixel_rng(seed, row * width + column);
            let cast = (&*group, blocked, &mut starts);
            let colour = self.shade_ready(ready, ray, cast, (&mut rng, rec), stats);
            put(at, colour);
        }
        group.clear();
    }

    /// The colour of a first hit made ready, its shadow rays cast ahead in `group` (`blocked`, the
    /// lanes blocked; `starts`, true until the group's first rays are told of): what
    /// [`SecondaryCaster::radiance`] gives for it, telling `rec` the same.
    fn shade_ready<R: Record>(
        &self,
        ready: &ReadyHit,
        ray: Ray,
        (group, blocked, starts): (&Group, u32, &mut bool),
        (rng, rec): (&mut Pcg32, &mut R),
        stats: &mut Stats,
    ) -> V3<f64> {
        let lighting = &self.prepared.lighting;
        let lights = lighting.lights.len();
        let lanes = ready.first..ready.first + lights;
        let own = (blocked >> ready.first) & ready.tested;
        if ready.tested != 0 {
            rec.any_hits_ahead(std::mem::take(starts));
            let taking = ready.tested << ready.first;
            tell_queries(
                (&group.rays, taking),
                &group.t_max,
                RayKind::Shadow,
                rec,
                stats,
            );
            stats.secondary.blocked += u64::from(own.count_ones());
        }
        let shadows = ShadowRays {
            cosines: &ready.cosines[..lights],
            rays: &group.rays[lanes.clone()],
            t_max: &group.t_max[lanes],
            tested: ready.tested,
        };
        let point = &ready.spot.point;
        // As `local` lights it without ambient occlusion: open everywhere.
        let local = self.lit(&ready.surface, 1.0, |light| {
            self.add_light(light, (0, &lighting.lights), point, (shadows, own), rec);
        });
        let lit = (&ready.surface, &ready.spot, local);
        self.with_onward((ready.hit, ray), 0, lit, (rng, rec), stats)
    }
}
