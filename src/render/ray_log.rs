//! Every ray a render casts, by kind, written down so it can be cast again: the peer bench replays
//! the rays of the Cornell box and of each effect scene through Embree (`intersect` for the kinds
//! that want the nearest hit, `occluded` for shadow and occlusion rays) and through raylab's own
//! queries, the ones the tracer called.

use rayon::prelude::*;

use super::ray_kinds::RayKind;
use super::secondary::{self, Record, SecondaryCaster};
use super::{Hit, Prepared, Ray, Stats, cast};

/// One ray as the tracer cast it: its kind, and how far it looks (t in (0, t_max); +∞ for the
/// nearest-hit kinds).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LoggedRay {
    pub kind: RayKind,
    pub ray: Ray,
    pub t_max: f64,
    /// True for the first ray of the shadow or occlusion rays cast together
    /// ([`cast::any_hits`]: a hit's occlusion rays, or its shadow rays); the packet's others
    /// follow it.
    pub starts_packet: bool,
    /// The bounces that led to a mirror or glass ray (0 for every other kind): a render casts its
    /// band's mirror and glass rays together bounce by bounce.
    pub depth: u32,
}

/// `rays` as the peers read them: per ray, seven little-endian f32s (origin x y z, direction
/// x y z, t_max; +∞ for the nearest-hit kinds).
pub fn as_f32s(rays: &[LoggedRay]) -> Vec<u8> {
    let mut bytes = Vec::with_capacity(rays.len() * 7 * 4);
    for logged in rays {
        let Ray { origin, dir } = logged.ray;
        for value in origin.iter().chain(&dir).chain([&logged.t_max]) {
            bytes.extend((*value as f32).to_le_bytes());
        }
    }
    bytes
}

impl LoggedRay {
    /// True for the kinds that ask only whether anything is in the way (shadow, occlusion).
    pub fn any_hit(&self) -> bool {
        matches!(self.kind, RayKind::Shadow | RayKind::Occlusion)
    }

    /// True for the kinds a render casts a bounce at a time with its neighbours' (samples, mirror
    /// and glass rays): the nearest-hit kinds other than primary rays.
    pub fn by_bounce(&self) -> bool {
        matches!(
            self.kind,
            RayKind::Sample | RayKind::Reflection | RayKind::Refraction
        )
    }

    /// Casts the ray again through the query the tracer used: true when it meets something.
    pub fn cast_again(&self, prepared: &Prepared, stats: &mut Stats) -> bool {
        if self.any_hit() {
            cast::any_hit(prepared, &self.ray, (0.0, self.t_max), stats)
        } else {
            cast::nearest_hit_between(prepared, self.ray, (0.0, self.t_max), stats).is_some()
        }
    }
}

/// Casts `rays` again as the tracer casts them, run of one kind by run ([`cast_run_again`],
/// each run of mirror, glass or sample rays put in casting order first unless it is). How many
/// met something.
pub fn cast_all_again(prepared: &Prepared, rays: &[LoggedRay], stats: &mut Stats) -> usize {
    rays.chunk_by(same_kind)
        .map(|run| {
            if run[0].by_bounce() && !run.is_sorted_by_key(|logged| logged.depth) {
                let mut by_bounce = run.to_vec();
                in_casting_order(&mut by_bounce);
                cast_run_again(prepared, &by_bounce, stats)
            } else {
                cast_run_again(prepared, run, stats)
            }
        })
        .sum()
}

/// Casts `run`, rays of one kind, again as the tracer casts them: primary rays sixteen at a time
/// in packets ([`cast::nearest_hits`]; the log's are sixteen neighbours along a row, a render's a
/// 4x4 tile), antialiasing samples, and mirror and glass rays sixteen at a time in the order
/// given (a render's are neighbouring pixels' in row order, a bounce at a time, cast ahead of
/// their shading, [`cast::nearest_hits_of_each`]: [`in_casting_order`] puts a log so), shadow
/// and occlusion rays in the packets the tracer cast them in ([`cast::any_hits`]). How many met
/// something. The peer bench's rows are a kind's rays, put in casting order before the clock
/// starts: a scan for the kind's runs and their order read every ray once more, 4% of the
/// Cornell box's primary rays' time.
pub fn cast_run_again(prepared: &Prepared, run: &[LoggedRay], stats: &mut Stats) -> usize {
    const PACKET: usize = 16;
    let Some(first) = run.first() else {
        return 0;
    };
    debug_assert!(run.iter().all(|r| same_kind(r, first)), "a run of one kind");
    if first.any_hit() {
        return any_hits_again(prepared, run, stats);
    }
    let mut met = 0;
    if first.by_bounce() {
        // Neighbouring pixels' samples, and their mirror and glass rays a bounce at a time,
        // together, as the render casts them.
        let count = |hit: Option<Hit>| met += usize::from(hit.is_some());
        cast::for_each_nearest_hit(prepared, run, |logged| logged.ray, stats, count);
        return met;
    }
    // Primary rays, sixteen neighbours at a time.
    let (packets, left) = run.as_chunks::<PACKET>();
    for packet in packets {
        let packet = packet.map(|logged| logged.ray);
        let mut hits = [None; PACKET];
        cast::nearest_hits(prepared, &packet, stats, &mut hits);
        met += hits.iter().filter(|hit| hit.is_some()).count();
    }
    met + left
        .iter()
        .filter(|ray| ray.cast_again(prepared, stats))
        .count()
}

/// [`cast_run_again`] for shadow or occlusion rays: in the packets the tracer cast them in, a
/// packet running from a ray that starts one to the next (sixteen at most).
fn any_hits_again(prepared: &Prepared, run: &[LoggedRay], stats: &mut Stats) -> usize {
    let Some(first) = run.first() else {
        return 0;
    };
    // One packet's lanes for them all, each packet writing its rays over the first: the lanes
    // past them hold an earlier packet's rays, which the query neither tests nor reports.
    // (Filled afresh for each packet, the sixteen rays cost a shadow ray 3% of its
    // instructions.)
    let mut rays = [first.ray; cast::TOGETHER];
    let mut t_max = [0.0; cast::TOGETHER];
    let mut met = 0;
    let mut rest = run;
    while !rest.is_empty() {
        prefetch_ahead(rest);
        let n = 1 + rest[1..]
            .iter()
            .take(cast::TOGETHER - 1)
            .take_while(|r| !r.starts_packet)
            .count();
        let (packet, left) = rest.split_at(n);
        rest = left;
        if let [alone] = packet {
            // As `cast::any_hits` casts a packet of one, without filling sixteen lanes.
            met += usize::from(alone.cast_again(prepared, stats));
            continue;
        }
        for (lane, logged) in packet.iter().enumerate() {
            rays[lane] = logged.ray;
            t_max[lane] = logged.t_max;
        }
        let blocked = cast::any_hits(prepared, (&rays, (1 << n) - 1), &t_max, stats);
        met += blocked.count_ones() as usize;
    }
    met
}

/// Asks the processor to start loading the logged rays two packets ahead of the first of `rays`:
/// a log of many rays comes from memory, and the packets' work does not wait for it then.
#[inline(always)]
fn prefetch_ahead(rays: &[LoggedRay]) {
    // The first line of each (a logged ray is 64 bytes). Prefetching the packet's bytes as one
    // run of lines took 2–3% more time on the AO scene's occlusion rays.
    for logged in rays.iter().skip(2 * cast::TOGETHER).take(cast::TOGETHER) {
        crate::render::kernels::prefetch_lines(std::ptr::from_ref(logged), 1);
    }
}

/// True for two neighbours in the log of one kind (the runs the replay casts together).
fn same_kind(a: &LoggedRay, b: &LoggedRay) -> bool {
    a.kind == b.kind
}

/// Puts `rays` (logged pixel by pixel) in the order the render casts them, which
/// [`cast_all_again`] otherwise makes for each call: each run of mirror, glass or sample rays
/// bounce by bounce, neighbours in row order. The peer bench orders its rays so before its clock
/// starts, as Embree's side gets its arrays made: a render never sorts them, it casts each bounce
/// of its band in turn.
pub fn in_casting_order(rays: &mut [LoggedRay]) {
    for same in rays.chunk_by_mut(same_kind) {
        if same[0].by_bounce() {
            same.sort_by_key(|logged| logged.depth);
        }
    }
}

/// Writes down each ray as the caster tells of it.
#[derive(Default)]
struct Log {
    rays: Vec<LoggedRay>,
    /// The next any-hit query starts a packet.
    packet_starts: bool,
    /// The last packet told of was cast ahead (rays cast ahead next may go on it).
    in_ahead: bool,
}

impl Log {
    fn push(&mut self, (kind, ray, t_max): (RayKind, Ray, f64), starts_packet: bool, depth: u32) {
        self.rays.push(LoggedRay {
            kind,
            ray,
            t_max,
            starts_packet,
            depth,
        });
    }
}

impl Record for Log {
    fn start(&mut self, kind: RayKind, depth: u32, ray: Ray) {
        self.push((kind, ray, f64::INFINITY), false, depth);
    }

    fn any_hits_together(&mut self) {
        self.packet_starts = true;
        self.in_ahead = false;
    }

    fn any_hits_ahead(&mut self, starts: bool) {
        // Rays cast ahead go on a packet only right after its own rays: after a packet cast when
        // asked (a mirror's hit's), they start a run of their own (the replay casts the runs from
        // one start to the next), so the log never joins rays cast apart.
        if starts || !self.in_ahead {
            self.packet_starts = true;
        }
        self.in_ahead = true;
    }

    fn pixel(&mut self, centre: Ray) {
        self.push((RayKind::Primary, centre, f64::INFINITY), false, 0);
    }

    fn any_hit_query(&mut self, kind: RayKind, ray: Ray, t_max: f64) {
        let starts = std::mem::take(&mut self.packet_starts);
        self.push((kind, ray, t_max), starts, 0);
    }
}

/// Every ray a render of `prepared` casts, pixel by pixel in row order: each pixel's centre ray
/// (primary), then the rays its colour takes (samples, shadow, reflection, refraction, occlusion
/// rays) in the order the tracer casts them.
pub fn rays_cast(prepared: &Prepared) -> Vec<LoggedRay> {
    let caster = secondary::applies(prepared).then(|| SecondaryCaster::new(prepared));
    let rows: Vec<Vec<LoggedRay>> = (0..prepared.height)
        .into_par_iter()
        .map(|row| {
            let mut log = Log::default();
            let mut stats = Stats::default();
            let centres = (0..prepared.width).map(|column| prepared.ray(row, column));
            let Some(caster) = &caster else {
                centres.for_each(|ray| log.pixel(ray));
                return log.rays;
            };
            // A row shaded as a render shades a band of rows (whose packets stay in a row).
            let met: Vec<(Ray, Option<Hit>)> = centres
                .map(|ray| (ray, cast::nearest_hit(prepared, ray, &mut stats)))
                .collect();
            caster.shade_band(row, &met, (&mut log, &mut stats), |_, _| {});
            log.rays
        })
        .collect();
    rows.concat()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::loading::assets::Embedded;
    use crate::render::render;
    use crate::scene::{Problem, Scene};

    /// The peers read seven little-endian f32s a ray, in the order the script's docs give, with
    /// +∞ kept for a nearest-hit ray's t_max.
    #[test]
    fn the_peers_read_seven_f32s_a_ray() {
        let logged = |origin, dir, t_max, kind| LoggedRay {
            kind,
            ray: Ray { origin, dir },
            t_max,
            starts_packet: false,
            depth: 0,
        };
        let rays = [
            logged(
                [1.0, -2.0, 0.5],
                [0.0, 1.0, 0.25],
                f64::INFINITY,
                RayKind::Primary,
            ),
            logged([0.1, 0.2, 0.3], [-1.0, 0.0, 0.0], 2.5, RayKind::Shadow),
        ];
        let bytes = as_f32s(&rays);
        let numbers: Vec<f32> = bytes
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect();
        assert_eq!(
            numbers,
            [
                1.0,
                -2.0,
                0.5,
                0.0,
                1.0,
                0.25,
                f32::INFINITY,
                0.1,
                0.2,
                0.3,
                -1.0,
                0.0,
                0.0,
                2.5
            ]
        );
    }

    /// A band's first hits' shadow rays are cast ahead, neighbours' together, and the log keeps
    /// those packets: the one-light scene's come sixteen to a packet, or nearly (shaded one hit
    /// at a time, each was a packet of one). Rays cast ahead never join a packet cast apart: when
    /// a mirror's hit's shadow ray, cast when asked, comes between two hits' cast ahead together,
    /// the second's starts a run of its own.
    #[test]
    fn shadow_rays_cast_ahead_stay_in_their_packets() {
        let path = format!(
            "{}/assets/scenes/effect-shadows.ron",
            env!("CARGO_MANIFEST_DIR")
        );
        let Ok(Problem::Render(scene)) =
            Scene::load(std::path::Path::new(&path)).map(|s| s.problem)
        else {
            panic!("the one-light scene is a render scene");
        };
        let prepared = Prepared::new(&scene, &Embedded).unwrap();
        let shadows: Vec<LoggedRay> = rays_cast(&prepared)
            .into_iter()
            .filter(|r| r.kind == RayKind::Shadow)
            .collect();
        let packets = shadows.iter().filter(|r| r.starts_packet).count();
        let per_packet = shadows.len() as f64 / packets as f64;
        assert!(per_packet > 12.0, "{per_packet:.2} shadow rays a packet");

        // Hit a's ray cast ahead, first of its packet; a's mirror's hit's, cast when asked; then
        // hits b's and c's, cast ahead in a's packet.
        let mut log = Log::default();
        for (x, told) in [
            (0.0, Some(true)),
            (1.0, None),
            (2.0, Some(false)),
            (3.0, Some(false)),
        ] {
            match told {
                Some(starts) => log.any_hits_ahead(starts),
                None => log.any_hits_together(),
            }
            let ray = Ray::new([x, 0.0, 0.0], [0.0, 0.0, 1.0]);
            log.any_hit_query(RayKind::Shadow, ray, 1.0);
        }
        let starts: Vec<bool> = log.rays.iter().map(|r| r.starts_packet).collect();
        assert_eq!(starts, [true, true, true, false]);
    }

    /// The log holds exactly the rays the render counts, kind by kind, and cast again they are
    /// blocked as often as in the render (the Cornell box and each effect scene, made small).
    #[test]
    fn the_log_holds_the_rays_the_render_casts() {
        for file in crate::render::ray_kinds::EFFECT_SCENES {
            let path = format!("{}/assets/scenes/{file}", env!("CARGO_MANIFEST_DIR"));
            let Ok(Problem::Render(mut scene)) =
                Scene::load(std::path::Path::new(&path)).map(|s| s.problem)
            else {
                panic!("{file} is a render scene");
            };
            scene.width = scene.width.min(24);
            scene.height = scene.height.min(16);
            let prepared = Prepared::new(&scene, &Embedded).unwrap();
            let (_, stats) = render(&prepared);
            let logged = rays_cast(&prepared);
            for kind in RayKind::ALL {
                let count = logged.iter().filter(|r| r.kind == kind).count() as u64;
                assert_eq!(count, stats.rays_of(kind), "{file}: {}", kind.name());
            }
            assert!(
                logged.len() as u64 > stats.rays,
                "{file}: no ray past the primary"
            );
            let mut again = Stats::default();
            let blocked = logged
                .iter()
                .filter(|r| r.any_hit() && r.cast_again(&prepared, &mut again))
                .count() as u64;
            assert_eq!(blocked, stats.secondary.blocked, "{file}");
            // Cast again in the packets the tracer cast them in, as blocked as alone.
            let any_hit: Vec<LoggedRay> = logged.iter().filter(|r| r.any_hit()).copied().collect();
            let in_packets = cast_all_again(&prepared, &any_hit, &mut again) as u64;
            assert_eq!(in_packets, stats.secondary.blocked, "{file}");
            // The whole log, every kind in the order logged, kind after kind: as each ray alone.
            let all = cast_all_again(&prepared, &logged, &mut again);
            let alone = logged
                .iter()
                .filter(|r| r.cast_again(&prepared, &mut again))
                .count();
            assert_eq!(all, alone, "{file}: the whole log");
            let packets = any_hit.iter().filter(|r| r.starts_packet).count();
            assert_eq!(
                packets > 0,
                !any_hit.is_empty(),
                "{file}: {packets} packets"
            );
            // The primary rays in packets meet what they met in the render.
            let primary: Vec<LoggedRay> = logged
                .iter()
                .filter(|r| r.kind == RayKind::Primary)
                .copied()
                .collect();
            let met = cast_all_again(&prepared, &primary, &mut again) as u64;
            assert_eq!(met, stats.hits, "{file}");
            // So do the samples and the mirror and glass rays, sixteen at a time.
            for kind in [RayKind::Sample, RayKind::Reflection, RayKind::Refraction] {
                let of_kind: Vec<LoggedRay> =
                    logged.iter().filter(|r| r.kind == kind).copied().collect();
                let met = cast_all_again(&prepared, &of_kind, &mut again);
                let alone = of_kind
                    .iter()
                    .filter(|r| r.cast_again(&prepared, &mut again))
                    .count();
                assert_eq!(met, alone, "{file}: {}", kind.name());
                // Put in casting order first and cast as one run (as the peer bench does), the
                // same.
                let mut ordered = of_kind.clone();
                in_casting_order(&mut ordered);
                assert!(ordered.is_sorted_by_key(|r| r.depth), "{file}");
                let met = cast_run_again(&prepared, &ordered, &mut again);
                assert_eq!(met, alone, "{file}: {} in casting order", kind.name());
            }
            // Casting order moves rays only within a run of mirror, glass or sample rays.
            let mut ordered = logged.clone();
            in_casting_order(&mut ordered);
            for (moved, was) in ordered.iter().zip(&logged) {
                assert_eq!(moved.kind, was.kind, "{file}");
                let may_move = matches!(
                    was.kind,
                    RayKind::Sample | RayKind::Reflection | RayKind::Refraction
                );
                assert!(may_move || moved == was, "{file}: {was:?}");
            }
        }
    }
}
