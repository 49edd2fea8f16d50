//! Casting one ray into a prepared scene: into each object's space, through its BVH, through the core's
//! intersection method; the nearest hit wins. The common bugs the app shows ([`Bug`]) are switched on
//! here.

use super::Bug;
use super::bvh::Bvh;
use super::crack_free::ShearedRay;
use super::kernels::Avx2;
use super::kernels::parallelogram4::Parallelogram4;
use super::object_index;
use super::objects::{Geometry, PreparedObject, PreparedTriangle, unit};
use super::{Hit, ParallelogramHit, Prepared, Ray, Stats, TriangleHit};
use crate::geometry::parallelogram::lean::solve_inside;
use crate::intersect::moller_trumbore;
use crate::intersect::{Case, Method};
use crate::math::linalg::V3;
use crate::math::linalg::sub;

/// The ray in an object's space: O' = M⁻¹ O as a point, D' = M⁻¹ D as a direction, not normalised,
/// so o' + t d' is M⁻¹ (o + t d) and t means the same in both spaces. Inlined: returned through
/// memory, its six numbers stalled the loads that read them back (store forwarding).
#[inline(always)]
pub fn to_object_space(
    object: &PreparedObject,
    ray: Ray,
    bug: Option<Bug>,
    stats: &mut Stats,
) -> Ray {
    let Some(inverse) = object.object_from_world else {
        return ray;
    };
    stats.transforms += 1;
    let origin = inverse.transform_point3(ray.origin.into()).to_array();
    let dir = inverse.transform_vector3(ray.dir.into()).to_array();
    if bug == Some(Bug::NormalizedDirection) {
        return Ray::new(origin, unit(dir));
    }
    Ray::new(origin, dir)
}

/// [`to_object_space`] where the object has a transform; else the ray itself, read where it lies
/// (a copy's stores stalled the loads that read it back).
#[inline(always)]
fn in_object_space<'a>(
    object: &PreparedObject,
    ray: &'a Ray,
    bug: Option<Bug>,
    stats: &mut Stats,
) -> std::borrow::Cow<'a, Ray> {
    match object.object_from_world {
        None => std::borrow::Cow::Borrowed(ray),
        Some(_) => std::borrow::Cow::Owned(to_object_space(object, *ray, bug, stats)),
    }
}

/// Tests one triangle: the method's decision (`watertight`: the crack-free test), or a bug's.
/// Inlined: its ray, passed through memory, stalled the loads that read it back.
#[inline(always)]
pub fn test_triangle(
    triangle: &PreparedTriangle,
    method: Method,
    bug: Option<Bug>,
    Ray { origin, dir }: Ray,
) -> Option<TriangleHit> {
    // Built only for the methods and bugs that take it (copying it for each ray costs).
    let case = || Case {
        tri: triangle.vertices,
        origin,
        dir,
    };
    // The renderer's `watertight` is the crack-free test; every other name runs the core's method.
    let correct =
        match method {
            Method::Watertight => ShearedRay::new(&origin, &dir)
                .and_then(|ray| ray.intersect(&triangle.vertices, 0.0)),
            // The core's Möller–Trumbore on the triangle in place (the same bits): the default for
            // lone triangles, tested by every ray of the image.
            Method::MollerTrumbore => moller_trumbore::hit(&triangle.vertices, &origin, &dir)
                .map(TriangleHit::from_values),
            _ => {
                let answer = method.run(&case());
                answer
                    .values
                    .filter(|_| answer.hit)
                    .map(TriangleHit::from_values)
            }
        };
    match bug {
        // Each bug accepts more than the correct test does: what the method hits stays hit (so the
        // image differs only by the bug), and the bug's own check, on Cramer's t, β, γ, adds the rest.
        Some(bug @ (Bug::AndForOr | Bug::NegativeT | Bug::VInsteadOfSum)) if correct.is_none() => {
            let [t, beta, gamma] = Method::Cramer.run(&case()).values?;
            let alpha = 1.0 - beta - gamma;
            let hit = match bug {
                Bug::AndForOr => t > 0.0 && (alpha >= 0.0 || beta >= 0.0 || gamma >= 0.0),
                Bug::NegativeT => t < 0.0 && alpha >= 0.0 && beta >= 0.0 && gamma >= 0.0,
                _ => t > 0.0 && beta >= 0.0 && gamma >= 0.0 && beta <= 1.0 && gamma <= 1.0,
            };
            hit.then_some(TriangleHit { beta, gamma, t })
        }
        _ => correct,
    }
}

/// Tests a parallelogram with the core's solver (seed 001, without its trace): (α, β, t) or a miss.
/// A ray whose t is surely beyond `t_max` (a nearer hit, the end of a shadow ray) or surely before
/// `t_min` (a secondary ray leaving the parallelogram itself) may be called a miss: the caller
/// would drop its hit.
fn test_parallelogram(
    [corner, e1, e2]: [&V3<f64>; 3],
    bug: Option<Bug>,
    Ray { origin, dir }: Ray,
    (t_min, t_max): (f64, f64),
) -> Option<ParallelogramHit> {
    if surely_outside([corner, e1, e2], &origin, &dir, (t_min, t_max)) {
        return None;
    }
    let inside = solve_inside([corner, e1, e2], &origin, &dir)?;
    let [alpha, beta, t] = inside.alpha_beta_t;
    let hit = inside.hit || (bug == Some(Bug::NegativeT) && t != 0.0);
    hit.then_some(ParallelogramHit { alpha, beta, t })
}

/// True when the ray's line meets the parallelogram's plane so far outside it (α or β beyond [0, 1]
/// by a margin a million times the rounding error) that seed 001's solver must find it outside too:
/// the solver is skipped (its answer would be a miss whatever the bug). Möller–Trumbore's (α, β)
/// for the system o + t d = c + α e1 + β e2, only where the system is far from singular. Also true
/// when the plane's t is beyond `t_max` by the same kind of margin, or before `t_min` by ten
/// thousand times the rounding error (the hit would be dropped: a shadow or occlusion ray leaving
/// the parallelogram sees its plane at t ≈ −offset / |d|, which a margin of a million times the
/// rounding error would not tell from 0).
#[inline]
fn surely_outside(
    [corner, e1, e2]: [&V3<f64>; 3],
    origin: &V3<f64>,
    dir: &V3<f64>,
    (t_min, t_max): (f64, f64),
) -> bool {
    use crate::math::linalg::{cross, dot};
    let l1 = |v: &V3<f64>| v[0].abs() + v[1].abs() + v[2].abs();
    let p = cross(dir, e2);
    let det = dot(e1, &p);
    let s = sub(origin, corner);
    let q = cross(&s, e1);
    // One division: each quotient below then carries one more rounding, a 2⁻⁵³ part of what the
    // margins allow. (Where 1/det overflows, α is not finite and the solver decides.)
    let inverse = 1.0 / det;
    let inverse_size = inverse.abs();
    let (alpha, beta) = (dot(&s, &p) * inverse, dot(dir, &q) * inverse);
    // |det| against |d|·|e1|·|e2| (1-norms bound the 2-norms' product from above).
    let conditioned = det.abs() > 1e-6 * l1(dir) * l1(e1) * l1(e2);
    let margin = |a: &V3<f64>, b: &V3<f64>| 1e-6 * (1.0 + l1(a) * l1(b) * inverse_size);
    let outside = |x: f64, m: f64| x < -m || x > 1.0 + m;
    // Möller–Trumbore's t = e2·q / |M|; the solver's t is (e1 × e2)·(o − c) / |M| rounded
    // otherwise: both within a few roundings of |e1| |e2| |o − c| / |M| (q = s × e1) from the
    // true t, a million times less than the margin. With |M| > 1e-200, underflow in the
    // numerators (below 1e-321) moves t by less than 1e-100.
    let off_range = || {
        let t = dot(e2, &q) * inverse;
        let error = t.abs() + l1(e1) * l1(e2) * l1(&s) * inverse_size;
        let beyond = t_max < f64::INFINITY && t - (1e-6 * error + 1e-100) > t_max;
        let before = t_min > f64::NEG_INFINITY && t + (1e-12 * error + 1e-100) < t_min;
        det.abs() > 1e-200 && t.is_finite() && (beyond || before)
    };
    conditioned
        && alpha.is_finite()
        && beta.is_finite()
        && (outside(alpha, margin(&s, &p)) || outside(beta, margin(dir, &q)) || off_range())
}

/// True when an object's triangles take the crack-free test: the method is `watertight` (the default
/// for meshes) and no bug is switched on. `watertight-exact` keeps the exact-deciding test.
pub fn crack_free_applies(prepared: &Prepared, object: &PreparedObject) -> bool {
    test_bug(prepared).is_none() && prepared.method_for(object) == Method::Watertight
}

/// The nearest hit of the crack-free test among `triangles` (through the BVH when there is one) with
/// 0 < t ≤ `t_max`, ties to the lower index; its `object` is left 0 for the caller to set.
fn nearest_crack_free(
    simd: Option<Avx2>,
    triangles: &[PreparedTriangle],
    bvh: Option<&Bvh>,
    ray: Ray,
    t_max: f64,
    stats: &mut Stats,
) -> Option<Hit> {
    let (primitive, hit) = match bvh {
        Some(bvh) => bvh.nearest_crack_free(
            simd,
            &ray,
            (0.0, t_max),
            &mut stats.box_tests,
            &mut stats.triangle_tests,
        )?,
        None => {
            let sheared = ShearedRay::new(&ray.origin, &ray.dir)?;
            stats.triangle_tests += triangles.len() as u64;
            let mut best: Option<(usize, TriangleHit)> = None;
            for (i, triangle) in triangles.iter().enumerate() {
                if let Some(hit) = sheared.intersect(&triangle.vertices, 0.0)
                    && hit.t <= best.map_or(t_max, |(_, b)| b.t)
                    && best.is_none_or(|(_, b)| hit.t < b.t)
                {
                    best = Some((i, hit));
                }
            }
            best?
        }
    };
    Some(Hit::triangle(0, primitive, hit))
}

/// The nearest hit among all objects; ties go to the earlier object and triangle.
pub fn nearest_hit(prepared: &Prepared, ray: Ray, stats: &mut Stats) -> Option<Hit> {
    let mut best: Option<Hit> = None;
    for index in 0..prepared.objects.len() {
        hit_object(prepared, index, ray, &mut best, stats);
    }
    best
}

/// True when `hit` is nearer than `best` (ties to the earlier object and triangle).
fn better(hit: &Hit, best: &Option<Hit>) -> bool {
    best.is_none_or(|b| {
        hit.t < b.t || (hit.t == b.t && (hit.object, hit.primitive) < (b.object, b.primitive))
    })
}

/// The nearest hits of `P` rays at once (neighbouring pixels), written into `best` (the caller's, so
/// a packet's hits are not copied on the way out): the same hits as [`nearest_hit`] for each.
/// Meshes taking the crack-free test are traversed by the packet together; other objects one ray at
/// a time.
#[inline]
pub fn nearest_hits<const P: usize>(
    prepared: &Prepared,
    rays: &[Ray; P],
    stats: &mut Stats,
    best: &mut [Option<Hit>; P],
) {
    *best = [None; P];
    let four = four_lanes::<P>(prepared);
    let every = super::ray::all_rays::<P>();
    // The lone triangles gathered in one hierarchy, tested together, in place of their objects.
    // (Without a method of the scene's, lone triangles take Möller–Trumbore: the index, which
    // gathers them, is not built for nothing.)
    let gathered = prepared
        .method
        .and_then(|_| prepared.object_index().gathered())
        .filter(|gathered| gathered.applies(prepared));
    // Rays inside a room of gathered walls test them last, the meshes' hits culling them.
    let walls_last = gathered.is_some_and(|gathered| gathered.surrounds(rays));
    let walls = |best: &mut [Option<Hit>; P], stats: &mut Stats| {
        if let Some(gathered) = gathered {
            let owner = |number| gathered.owner(number);
            packet_hits(prepared, &gathered.bvh, (rays, every), best, stats, owner);
        }
    };
    if !walls_last {
        walls(best, stats);
    }
    // Where a ray alone would walk the object index, a mesh is walked only by the packet's rays
    // that meet its box before their hit so far, and only they are moved into its space.
    // The packet's box numbers are made when the first mesh asks (a scene of lone triangles and
    // floors has none to ask: made for every packet, they took 8% of the one-light scene's).
    #[cfg(target_arch = "x86_64")]
    let mut boxes = object_index::PacketBoxes::zero();
    #[cfg(target_arch = "x86_64")]
    let culling =
        four.filter(|_| object_index::applies(prepared) && rays.iter().all(Ray::is_finite));
    #[cfg(target_arch = "x86_64")]
    let mut boxes_made = false;
    for (index, object) in prepared.objects.iter().enumerate() {
        if gathered.is_some_and(|gathered| gathered.holds(index)) {
            continue;
        }
        let bvh = match &object.geometry {
            Geometry::Triangles { bvh: Some(bvh), .. } if crack_free_applies(prepared, object) => {
                bvh
            }
            Geometry::Triangles {
                triangles,
                bvh: None,
            } if four.is_some_and(|avx2| {
                lone_hits(avx2, prepared, (index, triangles), rays, best, stats)
            }) =>
            {
                continue;
            }
            #[cfg(target_arch = "x86_64")]
            Geometry::Triangles {
                triangles,
                bvh: None,
            } if let Some(avx2) = four
                && P <= cast_lone::MOST
                && lone_world_triangles(prepared, object).is_some() =>
            {
                cast_lone::crack_free_hits(avx2, (index, triangles), rays, best, stats);
                continue;
            }
            Geometry::Parallelogram { .. }
                if let Some(lanes) = parallelogram_lanes(four, object) =>
            {
                parallelogram_hits(prepared, (index, lanes), rays, best, stats);
                continue;
            }
            _ => {
                for (best, ray) in best.iter_mut().zip(rays) {
                    hit_object(prepared, index, *ray, best, stats);
                }
                continue;
            }
        };
        #[cfg(target_arch = "x86_64")]
        let taking = culling.map_or(every, |avx2| {
            if !boxes_made {
                boxes.fill(avx2, rays);
                boxes_made = true;
            }
            let t_max = reaches(best);
            let index_boxes = prepared.object_index();
            index_boxes.packet_meets(avx2, &boxes, index, &t_max, &mut stats.box_tests)
        });
        #[cfg(not(target_arch = "x86_64"))]
        let taking = every;
        if taking == 0 {
            continue;
        }
        // An untransformed mesh takes the packet's own rays, not a copy.
        let moved: [Ray; P];
        let local = match object.object_from_world {
            None => rays,
            Some(_) => {
                moved = taking_rays_in(object, (rays, taking), prepared.bug, stats);
                &moved
            }
        };
        packet_hits(prepared, bvh, (local, taking), best, stats, |primitive| {
            (index, primitive)
        });
    }
    // A packet whose rays' hits so far all lie short of every gathered triangle's box skips the
    // walk: it would find nothing nearer.
    if walls_last && !gathered.is_some_and(|gathered| gathered.beyond_reach(rays, &reaches(best))) {
        walls(best, stats);
    }
}

/// How far each of the first `N` rays of a packet still looks: its hit so far, or +∞.
#[inline(always)]
fn reaches<const N: usize>(best: &[Option<Hit>]) -> [f64; N] {
    std::array::from_fn(|lane| best[lane].map_or(f64::INFINITY, |hit| hit.t))
}

/// Walks `bvh` with the packet's rays of `taking` (in its space), each up to its hit so far, keeping
/// the nearer hits in `best`; `owner` names the object and triangle of the hierarchy's triangle.
#[inline(always)]
fn packet_hits<const P: usize>(
    prepared: &Prepared,
    bvh: &Bvh,
    (rays, taking): (&[Ray; P], u32),
    best: &mut [Option<Hit>; P],
    stats: &mut Stats,
    owner: impl Fn(usize) -> (usize, usize),
) {
    let t_max = reaches(best);
    let mut hits = [None; P];
    let (boxes, triangles) = (&mut stats.box_tests, &mut stats.triangle_tests);
    let packet = (rays, taking);
    bvh.nearest_crack_free_packet_of(prepared.simd, packet, t_max, boxes, triangles, &mut hits);
    for (best, hit) in best.iter_mut().zip(&hits) {
        if let Some((number, hit)) = *hit {
            let (object, primitive) = owner(number);
            offer(best, Hit::triangle(object, primitive, hit));
        }
    }
}

/// True when some object takes the crack-free test: then rays cast together in packets
/// ([`nearest_hits`]) share the packet walk, which pays; otherwise each would test every object
/// alone, without the object index.
pub fn packets_pay(prepared: &Prepared) -> bool {
    prepared
        .objects
        .iter()
        .any(|object| crack_free_applies(prepared, object))
}

/// The nearest hits with t in (0, ∞) of `P` rays at once, written into `best`: the same hits as
/// [`nearest_hit_between`] for each (the antialiasing samples of neighbouring pixels).
///
/// [`nearest_hits`] asks each object what [`nearest_hit_between`] asks it, except that a primary
/// ray also takes a parallelogram's hit at t = 0 (and a bug's at t < 0). So where its hit has
/// t > 0, no hit at t ≤ 0 was offered (the nearest would have been kept) and the two searches
/// saw the same candidates; a ray whose hit has t ≤ 0 is cast again alone.
pub fn nearest_hits_between<const P: usize>(
    prepared: &Prepared,
    rays: &[Ray; P],
    stats: &mut Stats,
    best: &mut [Option<Hit>; P],
) {
    nearest_hits(prepared, rays, stats, best);
    for (best, ray) in best.iter_mut().zip(rays) {
        if best.is_some_and(|hit| hit.t <= 0.0 || hit.t.is_nan()) {
            *best = nearest_hit_between(prepared, *ray, (0.0, f64::INFINITY), stats);
        }
    }
}

/// The nearest hit with t in (0, ∞) of each ray (the hits of [`nearest_hit_between`]):
/// [`TOGETHER`] at a time through [`nearest_hits_between`] where [`packets_pay`] (the last few in
/// a padded packet, from [`PADDED_FROM`]), the rest alone.
pub fn nearest_hits_of_each(
    prepared: &Prepared,
    rays: &[Ray],
    stats: &mut Stats,
) -> Vec<Option<Hit>> {
    let mut hits = Vec::with_capacity(rays.len());
    for_each_nearest_hit(prepared, rays, |ray| *ray, stats, |hit| hits.push(hit));
    hits
}

/// The fewest rays left over after the whole packets that are cast as one more packet, padded with
/// copies of the last: fewer are cast alone. (Each run of a bounce's glass rays ends in such a
/// tail: cast as a packet, the effect-refraction scene's glass rays take 2.1% fewer instructions.)
const PADDED_FROM: usize = 4;

/// [`nearest_hits_of_each`] over `items` (each gives its ray by `ray_of`), telling `found` each
/// item's hit in order, with no list made (the peer bench's replay counts them as it goes).
pub fn for_each_nearest_hit<T>(
    prepared: &Prepared,
    items: &[T],
    ray_of: impl Fn(&T) -> Ray,
    stats: &mut Stats,
    mut found: impl FnMut(Option<Hit>),
) {
    let alone = if packets_pay(prepared) {
        let (packets, rest) = items.as_chunks::<TOGETHER>();
        for packet in packets {
            let rays = packet.each_ref().map(&ray_of);
            let mut hits = [None; TOGETHER];
            nearest_hits_between(prepared, &rays, stats, &mut hits);
            hits.into_iter().for_each(&mut found);
        }
        if let Some(last) = rest.last().filter(|_| rest.len() >= PADDED_FROM) {
            // The last ray's copies fill the packet; their hits are dropped.
            let last = ray_of(last);
            let rays = std::array::from_fn(|r| rest.get(r).map_or(last, &ray_of));
            let mut hits = [None; TOGETHER];
            nearest_hits_between(prepared, &rays, stats, &mut hits);
            hits[..rest.len()].iter().copied().for_each(&mut found);
            items.len()
        } else {
            items.len() - rest.len()
        }
    } else {
        0
    };
    for item in &items[alone..] {
        found(nearest_hit_between(
            prepared,
            ray_of(item),
            (0.0, f64::INFINITY),
            stats,
        ));
    }
}

/// The bug the primitive tests see: shadow acne moves secondary rays' origins, not a test.
fn test_bug(prepared: &Prepared) -> Option<Bug> {
    prepared.bug.filter(|&bug| bug != Bug::ShadowAcne)
}

/// Hands a packet's rays to `four`, four at a time, in `object`'s space, with their hits so far:
/// what the four-lane kernels take. An untransformed object (a floor) gets the packet's own rays,
/// written long before, so the kernel's loads need not wait for fresh copies' stores.
#[inline(always)]
fn each_four<const P: usize>(
    object: &PreparedObject,
    rays: &[Ray; P],
    best: &mut [Option<Hit>; P],
    stats: &mut Stats,
    mut four: impl FnMut(&[Ray; 4], &mut [Option<Hit>], &mut Stats),
) {
    let (groups, _) = rays.as_chunks::<4>();
    for (group, world) in groups.iter().enumerate() {
        let moved: [Ray; 4];
        let local = match object.object_from_world {
            None => world,
            Some(_) => {
                moved = world.map(|ray| to_object_space(object, ray, None, stats));
                &moved
            }
        };
        four(local, &mut best[4 * group..4 * group + 4], stats);
    }
}

/// The AVX2 proof when a packet of `P` rays may take the four-lane kernels: the processor has AVX2,
/// the packet splits into fours, and no bug changes the test.
#[inline(always)]
fn four_lanes<const P: usize>(prepared: &Prepared) -> Option<Avx2> {
    let allowed = P.is_multiple_of(4) && test_bug(prepared).is_none();
    prepared.simd.filter(|_| allowed)
}

/// Object `index`'s lone triangles by Möller–Trumbore, four rays at a time
/// ([`super::kernels::moller_trumbore4`]: the same arithmetic, so the same hits as [`hit_object`]),
/// where [`four_lanes`] allows. False when the object takes another method (then nothing was done).
#[inline(always)]
fn lone_hits<const P: usize>(
    avx2: Avx2,
    prepared: &Prepared,
    (index, triangles): (usize, &[PreparedTriangle]),
    rays: &[Ray; P],
    best: &mut [Option<Hit>; P],
    stats: &mut Stats,
) -> bool {
    use super::kernels::moller_trumbore4::{Rays4, moller_trumbore};
    let object = &prepared.objects[index];
    if prepared.method_for(object) != Method::MollerTrumbore {
        return false;
    }
    each_four(object, rays, best, stats, |local, best, stats| {
        let four = Rays4 {
            origin: std::array::from_fn(|k| local.map(|ray| ray.origin[k])),
            dir: std::array::from_fn(|k| local.map(|ray| ray.dir[k])),
        };
        for (primitive, triangle) in triangles.iter().enumerate() {
            stats.triangle_tests += 4;
            let (mut hit, [t, beta, gamma]) = moller_trumbore(avx2, &triangle.vertices, &four);
            while hit != 0 {
                let lane = hit.trailing_zeros() as usize;
                hit &= hit - 1;
                let hit = TriangleHit {
                    beta: beta[lane],
                    gamma: gamma[lane],
                    t: t[lane],
                };
                offer(&mut best[lane], Hit::triangle(index, primitive, hit));
            }
        }
    });
    true
}

/// Lone triangles (no hierarchy, in world space) by the crack-free test, a triangle against four
/// of a packet's rays at a time.
#[cfg(target_arch = "x86_64")]
mod cast_lone {
    use super::{Avx2, Hit, PreparedTriangle, Ray, ShearedRay, Stats, bits, offer};
    use crate::render::kernels::crack_free4::{Quad, RaysTogether, intersect_rays4};

    /// The most rays [`crack_free_hits`] takes at once (a [`RaysTogether`] holds sixteen).
    pub(super) const MOST: usize = 16;

    /// Object `index`'s lone triangles in world space against a packet's rays (at most [`MOST`]),
    /// keeping the nearer hits in `best`: the same hits as [`super::hit_object`] finds for each
    /// ray (the nearest, ties to the earlier object and triangle) and the same tests counted. The
    /// rays whose sheared axes are the first ray's take each triangle four at a time
    /// (`intersect_rays4`: each lane decides as `ShearedRay::intersect` decides for its ray, with
    /// the same numbers); the others, and the lanes it leaves, one at a time. One lone triangle
    /// (the one-light scene's) took a primary ray 58% of its time one ray at a time.
    #[inline(always)]
    pub(super) fn crack_free_hits<const P: usize>(
        avx2: Avx2,
        (index, triangles): (usize, &[PreparedTriangle]),
        rays: &[Ray; P],
        best: &mut [Option<Hit>; P],
        stats: &mut Stats,
    ) {
        let sheared: [Option<ShearedRay>; P] =
            std::array::from_fn(|r| ShearedRay::new(&rays[r].origin, &rays[r].dir));
        let mut together = RaysTogether::default();
        let mut made = 0u32;
        for (r, ray) in sheared.iter().enumerate() {
            if let Some(ray) = ray {
                made |= 1 << r;
                together.offer(r, ray);
            }
        }
        stats.triangle_tests += u64::from(made.count_ones()) * triangles.len() as u64;
        let alone = made & !together.rays;
        let one_ray = |r: usize, primitive: usize, best: &mut [Option<Hit>; P]| {
            if let Some(ray) = &sheared[r]
                && let Some(hit) = ray.intersect(&triangles[primitive].vertices, 0.0)
            {
                offer(&mut best[r], Hit::triangle(index, primitive, hit));
            }
        };
        for (primitive, triangle) in triangles.iter().enumerate() {
            let quad = Quad::new(std::slice::from_ref(&triangle.vertices));
            for (group, four) in together.quads.iter().enumerate() {
                let lanes = (together.rays >> (4 * group)) & 0b1111;
                if lanes == 0 {
                    continue;
                }
                let found = intersect_rays4(avx2, (together.axes, four), (&quad, 0), 0.0, lanes);
                for lane in bits(found.hit) {
                    let hit = Hit::triangle(index, primitive, found.hit(lane));
                    offer(&mut best[4 * group + lane], hit);
                }
                for lane in bits(found.again) {
                    one_ray(4 * group + lane, primitive, best);
                }
            }
            for r in bits(alone) {
                one_ray(r, primitive, best);
            }
        }
    }
}

/// Object `index`, a parallelogram, four rays at a time where [`four_lanes`] allows
/// ([`super::kernels::parallelogram4`]: seed 001's solver in lanes, the same bits, so the same hits
/// as [`hit_object`]); a ray whose t is beyond its nearest hit so far is dropped before its α and β
/// are computed. Rays the kernel leaves to the one-ray solver go through [`test_parallelogram`].
#[inline(always)]
fn parallelogram_hits<const P: usize>(
    prepared: &Prepared,
    (index, (solver, shape)): (usize, (Parallelogram4, [&V3<f64>; 3])),
    rays: &[Ray; P],
    best: &mut [Option<Hit>; P],
    stats: &mut Stats,
) {
    let object = &prepared.objects[index];
    each_four(object, rays, best, stats, |local, best, stats| {
        let t_max = reaches(best);
        stats.parallelogram_tests += 4;
        let found = solver.solve(local, &t_max);
        for (lane, best) in best.iter_mut().enumerate() {
            let hit = if found.rare & (1 << lane) != 0 {
                let range = (f64::NEG_INFINITY, t_max[lane]);
                test_parallelogram(shape, None, local[lane], range)
            } else {
                let hit = found.hit & (1 << lane) != 0;
                hit.then(|| ParallelogramHit {
                    alpha: found.alpha[lane],
                    beta: found.beta[lane],
                    t: found.t[lane],
                })
            };
            if let Some(hit) = hit {
                offer(best, Hit::parallelogram(index, hit));
            }
        }
    });
}

/// Keeps `hit` in `best` if it is nearer (ties go to the earlier object and triangle).
#[inline(always)]
fn offer(best: &mut Option<Hit>, hit: Hit) {
    if better(&hit, best) {
        *best = Some(hit);
    }
}

/// How an object's triangles are tested one at a time: the object, its method, the bug, and the
/// ray in its space.
struct TriangleTest<'a> {
    index: usize,
    method: Method,
    bug: Option<Bug>,
    ray: &'a Ray,
}

/// Tests triangle `primitive` and keeps the hit in `best` if nearer; the hit's t.
#[inline(always)]
fn keep_nearer(
    test: &TriangleTest,
    (primitive, triangle): (usize, &PreparedTriangle),
    best: &mut Option<Hit>,
    stats: &mut Stats,
) -> Option<f64> {
    stats.triangle_tests += 1;
    let hit = test_triangle(triangle, test.method, test.bug, *test.ray)?;
    offer(best, Hit::triangle(test.index, primitive, hit));
    Some(hit.t)
}

/// Tests object `index` against the ray (world space), keeping the nearer hit in `best`.
fn hit_object(
    prepared: &Prepared,
    index: usize,
    ray: Ray,
    best: &mut Option<Hit>,
    stats: &mut Stats,
) {
    let object = &prepared.objects[index];
    {
        let local = to_object_space(object, ray, prepared.bug, stats);
        match &object.geometry {
            Geometry::Triangles { triangles, bvh } if crack_free_applies(prepared, object) => {
                let t_max = best.map_or(f64::INFINITY, |b| b.t);
                if let Some(hit) = nearest_crack_free(
                    prepared.simd,
                    triangles,
                    bvh.as_deref(),
                    local,
                    t_max,
                    stats,
                ) {
                    offer(
                        best,
                        Hit {
                            object: index,
                            ..hit
                        },
                    );
                }
            }
            Geometry::Triangles { triangles, bvh } => {
                let t_max = best.map_or(f64::INFINITY, |b| b.t);
                let one = TriangleTest {
                    index,
                    method: prepared.method_for(object),
                    bug: prepared.bug,
                    ray: &local,
                };
                let mut test = |primitive: usize| {
                    keep_nearer(&one, (primitive, &triangles[primitive]), best, stats)
                };
                // The BVH culls by the triangles' boxes; `and`-for-`or` and v ≤ 1 accept points
                // outside them, so those bugs test every triangle.
                let culls = !matches!(prepared.bug, Some(Bug::AndForOr | Bug::VInsteadOfSum));
                match bvh.as_ref().filter(|_| culls) {
                    Some(bvh) => {
                        // Accepting t < 0 (a bug) makes the ray a whole line.
                        let t_min = match prepared.bug {
                            Some(Bug::NegativeT) => f64::NEG_INFINITY,
                            _ => 0.0,
                        };
                        let mut box_tests = 0;
                        bvh.traverse(&local, t_min, t_max, &mut box_tests, &mut test);
                        stats.box_tests += box_tests;
                    }
                    // Lone triangles: called in place, not through `test` (whose captured ray
                    // was read back from memory at a stall on each call).
                    None => {
                        for each in triangles.iter().enumerate() {
                            keep_nearer(&one, each, best, stats);
                        }
                    }
                }
            }
            Geometry::Parallelogram { corner, e1, e2, .. } => {
                stats.parallelogram_tests += 1;
                let t_max = best.map_or(f64::INFINITY, |b| b.t);
                let range = (f64::NEG_INFINITY, t_max);
                if let Some(hit) = test_parallelogram([corner, e1, e2], prepared.bug, local, range)
                {
                    offer(best, Hit::parallelogram(index, hit));
                }
            }
        }
    }
}

/// What a secondary ray looks for: the nearest hit (reflected, refracted rays) or any (shadow and
/// occlusion rays, which stop at the first).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Find {
    Nearest,
    Any,
}

/// The nearest hit among all objects with `t_min < t ≤ t_max` (ties as [`nearest_hit`]): secondary
/// rays, through the same transforms, methods and BVHs as primary rays.
pub fn nearest_hit_between(
    prepared: &Prepared,
    ray: Ray,
    (t_min, t_max): (f64, f64),
    stats: &mut Stats,
) -> Option<Hit> {
    let Some(index) = object_index::for_ray(prepared, &ray) else {
        return nearest_of_each_object(prepared, ray, (t_min, t_max), stats);
    };
    let mut best: Option<Hit> = None;
    let mut boxes = 0;
    index.visit::<false>(
        prepared.simd,
        &ray,
        (t_min, t_max),
        &mut boxes,
        |object, t_max| nearer(prepared, (object, ray), (t_min, t_max), &mut best, stats),
    );
    stats.box_tests += boxes;
    best
}

/// [`nearest_hit_between`] testing every object in turn, without the index.
pub(super) fn nearest_of_each_object(
    prepared: &Prepared,
    ray: Ray,
    (t_min, mut t_max): (f64, f64),
    stats: &mut Stats,
) -> Option<Hit> {
    let mut best: Option<Hit> = None;
    for index in 0..prepared.objects.len() {
        t_max = nearer(prepared, (index, ray), (t_min, t_max), &mut best, stats);
    }
    best
}

/// Keeps object `index`'s hit in (t_min, t_max] in `best` if nearer; the nearest t so far.
#[inline(always)]
fn nearer(
    prepared: &Prepared,
    (index, ray): (usize, Ray),
    range: (f64, f64),
    best: &mut Option<Hit>,
    stats: &mut Stats,
) -> f64 {
    if let Some(hit) = object_hit_between(prepared, index, ray, range, Find::Nearest, stats) {
        offer(best, hit);
    }
    best.map_or(range.1, |b| b.t)
}

/// True when anything is hit with `t_min < t < t_max`: an any-hit query that stops at the first hit
/// (shadow and occlusion rays; a surface exactly at the light does not hide it).
///
/// The ray is read where it lies, not copied: a copy's stores stalled the loads that read it back
/// (store forwarding), a sixth of a lone shadow ray's time.
pub fn any_hit(prepared: &Prepared, ray: &Ray, range: (f64, f64), stats: &mut Stats) -> bool {
    let Some(index) = object_index::for_ray(prepared, ray) else {
        return any_of_each_object(prepared, ray, range, stats);
    };
    let mut blocked = false;
    let mut boxes = 0;
    // The first object in the way ends the walk (t_max −∞ is below every box).
    index.visit::<true>(prepared.simd, ray, range, &mut boxes, |object, t_max| {
        blocked = object_blocks(prepared, object, ray, range, stats);
        if blocked { f64::NEG_INFINITY } else { t_max }
    });
    stats.box_tests += boxes;
    blocked
}

/// [`any_hit`] for up to sixteen rays together (a hit's occlusion rays, or its shadow rays): the
/// rays of `taking` (a bit set), ray r up to `t_max[r]`, from t = 0; the set of those blocked, each
/// answered as [`any_hit`] answers it. Through the object index, the rays together; each object
/// whose box some of them meet is then tested ray by ray (a mesh's hierarchy walked by each ray
/// alone through the f32 test of a node's four boxes at once, [`Bvh::occluded`]: a packet walk,
/// [`Bvh::occluded_packet_of`], met a mesh with three rays of eight on average and took more
/// time). Where the index does not apply, or a ray's numbers are not finite, each ray takes
/// [`any_hit`].
pub fn any_hits(
    prepared: &Prepared,
    (rays, taking): (&[Ray; TOGETHER], u32),
    t_max: &[f64; TOGETHER],
    stats: &mut Stats,
) -> u32 {
    let each_ray = |stats: &mut Stats| {
        let mut blocked = 0;
        for r in bits(taking) {
            blocked |= u32::from(any_hit(prepared, &rays[r], (0.0, t_max[r]), stats)) << r;
        }
        blocked
    };
    // One ray (a scene with one light) goes alone: a packet's set-up would cost it more.
    if taking.count_ones() < 2
        || !bits(taking).all(|r| rays[r].is_finite())
        || !object_index::applies(prepared)
    {
        return each_ray(stats);
    }
    // The index walks the packet's first four or eight lanes where its rays are there (a hit's
    // shadow rays, one per light; its occlusion rays): each node's test then skips no empty four.
    if taking < 1 << 4 {
        walk_index::<4>(prepared, (rays, taking), t_max, stats)
    } else if taking < 1 << 8 {
        walk_index::<8>(prepared, (rays, taking), t_max, stats)
    } else {
        walk_index::<TOGETHER>(prepared, (rays, taking), t_max, stats)
    }
}

/// [`any_hits`] through the object index, its walk taking the packet's first `P` lanes, which
/// hold every ray of `taking`.
#[inline(always)]
fn walk_index<const P: usize>(
    prepared: &Prepared,
    (rays, taking): (&[Ray; TOGETHER], u32),
    t_max: &[f64; TOGETHER],
    stats: &mut Stats,
) -> u32 {
    const { assert!(P <= TOGETHER && P.is_multiple_of(4)) };
    let (Some(first), Some(first_t_max)) = (rays.first_chunk::<P>(), t_max.first_chunk::<P>())
    else {
        unreachable!("a packet's {TOGETHER} lanes hold its first {P}")
    };
    let mut boxes = 0;
    // Each ray's sheared form in world space, made when an untransformed object first needs it.
    let mut sheared = [None; TOGETHER];
    let blocked = prepared.object_index().visit_any(
        prepared.simd,
        (first, taking),
        (0.0, first_t_max),
        &mut boxes,
        |object, rays_in| {
            let tested = (rays, rays_in);
            objects_block(prepared, object, (tested, &mut sheared), t_max, stats)
        },
    );
    stats.box_tests += boxes;
    blocked
}

/// Which of the rays of `taking` the lone triangles of an untransformed object taking the
/// crack-free test block within (0, t_max), `sheared` holding each ray's sheared form once made:
/// what [`object_blocks`] answers, without making it again for each object.
fn lone_triangles_block(
    triangles: &[PreparedTriangle],
    (rays, taking): (&[Ray; TOGETHER], u32),
    sheared: &mut WorldSheared,
    t_max: &[f64; TOGETHER],
    stats: &mut Stats,
) -> u32 {
    let mut blocked = 0;
    for r in bits(taking) {
        let made = sheared[r].get_or_insert_with(|| ShearedRay::new(&rays[r].origin, &rays[r].dir));
        if let Some(ray) = made
            && lone_triangle_blocks(triangles, ray, t_max[r], stats)
        {
            blocked |= 1 << r;
        }
    }
    blocked
}

/// An object's triangles when they are lone triangles in world space taking the crack-free test
/// (no hierarchy, no transform): the ones an any-hit query tests directly.
fn lone_world_triangles<'a>(
    prepared: &Prepared,
    object: &'a PreparedObject,
) -> Option<&'a [PreparedTriangle]> {
    match &object.geometry {
        Geometry::Triangles {
            triangles,
            bvh: None,
        } if object.object_from_world.is_none() && crack_free_applies(prepared, object) => {
            Some(triangles)
        }
        _ => None,
    }
}

/// True when one of `triangles` (in world space, taking the crack-free test) is hit by the sheared
/// `ray` at 0 < t < t_max; counts the triangles tested.
#[inline(always)]
fn lone_triangle_blocks(
    triangles: &[PreparedTriangle],
    ray: &ShearedRay,
    t_max: f64,
    stats: &mut Stats,
) -> bool {
    triangles.iter().any(|triangle| {
        stats.triangle_tests += 1;
        ray.intersect(&triangle.vertices, 0.0)
            .is_some_and(|hit| hit.t < t_max)
    })
}

/// The positions of `mask`'s set bits, lowest first (the rays of a packet that take part).
#[inline(always)]
pub fn bits(mut mask: u32) -> impl Iterator<Item = usize> {
    std::iter::from_fn(move || {
        let bit = mask.trailing_zeros() as usize;
        mask &= mask.wrapping_sub(1);
        (bit < 32).then_some(bit)
    })
}

/// Each ray's sheared form in world space, once made (`Some`; `Some(None)` for a ray without one).
type WorldSheared = [Option<Option<ShearedRay>>; TOGETHER];

/// Rays cast together by [`any_hits`]: the packet of the BVH's eight-ray box test, twice over.
pub const TOGETHER: usize = super::kernels::narrow::RAYS;

/// Which of the rays of `taking` object `index` blocks within (0, t_max): a mesh taking the
/// crack-free test for them all at once, anything else ray by ray ([`object_blocks`]).
fn objects_block(
    prepared: &Prepared,
    index: usize,
    ((rays, taking), sheared): ((&[Ray; TOGETHER], u32), &mut WorldSheared),
    t_max: &[f64; TOGETHER],
    stats: &mut Stats,
) -> u32 {
    let object = &prepared.objects[index];
    if let Some(triangles) = lone_world_triangles(prepared, object) {
        return lone_triangles_block(triangles, (rays, taking), sheared, t_max, stats);
    }
    if let Some((solver, shape)) = parallelogram_lanes(prepared.simd, object) {
        return parallelogram_blocks(
            prepared,
            (object, shape, &solver),
            (rays, taking),
            t_max,
            stats,
        );
    }
    let mut blocked = 0;
    for r in bits(taking) {
        let range = (0.0, t_max[r]);
        // Each lane keeps its own last blocker: a hit's shadow rays to its lights and its
        // occlusion rays go every way, and lane r is the same light's ray hit after hit.
        let ray_blocked =
            Bvh::in_blocker_lane(r, || object_blocks(prepared, index, &rays[r], range, stats));
        blocked |= u32::from(ray_blocked) << r;
    }
    blocked
}

/// The rays of `taking` in `object`'s space, each made once (the other lanes keep the world's
/// rays: a four-lane kernel neither tests nor reports them).
fn taking_rays_in<const N: usize>(
    object: &PreparedObject,
    (rays, taking): (&[Ray; N], u32),
    bug: Option<Bug>,
    stats: &mut Stats,
) -> [Ray; N] {
    let mut local = *rays;
    for r in bits(taking) {
        local[r] = to_object_space(object, rays[r], bug, stats);
    }
    local
}

/// Which of the rays of `taking` a parallelogram blocks within (0, t_max), four rays at a time
/// through seed 001's solver in lanes ([`Parallelogram4`], the same bits as the one-ray solver),
/// the rays it leaves to the one-ray solver through [`test_parallelogram`]: what
/// [`object_blocks`] answers (a hit with 0 < t ≤ the float below t_max, that is t < t_max). An
/// untransformed parallelogram (a floor, a wall) reads the packet's own rays, in place.
fn parallelogram_blocks(
    prepared: &Prepared,
    (object, shape, solver): (&PreparedObject, [&V3<f64>; 3], &Parallelogram4),
    (rays, taking): (&[Ray; TOGETHER], u32),
    t_max: &[f64; TOGETHER],
    stats: &mut Stats,
) -> u32 {
    let (groups, _) = rays.as_chunks::<4>();
    let (ends, _) = t_max.as_chunks::<4>();
    let mut blocked = 0;
    for (group, (world, ends)) in groups.iter().zip(ends).enumerate() {
        let lanes = (taking >> (4 * group)) & 0b1111;
        if lanes == 0 {
            continue;
        }
        let moved: [Ray; 4];
        let local = match object.object_from_world {
            None => world,
            Some(_) => {
                moved = taking_rays_in(object, (world, lanes), prepared.bug, stats);
                &moved
            }
        };
        stats.parallelogram_tests += u64::from(lanes.count_ones());
        let found = solver.solve_between(local, lanes, ends);
        let mut found_blocked = found.hit;
        for lane in bits(found.rare) {
            found_blocked |= u32::from(blocks_alone(shape, local[lane], ends[lane])) << lane;
        }
        blocked |= found_blocked << (4 * group);
    }
    blocked
}

/// True when the one-ray solver (through its prefilter) finds the parallelogram hit with
/// 0 < t < t_end: what a ray the four-lane solver leaves to it is answered by.
fn blocks_alone(shape: [&V3<f64>; 3], ray: Ray, t_end: f64) -> bool {
    // The largest float below t_end: the same open interval.
    let limit = t_end.next_down();
    let hit = test_parallelogram(shape, None, ray, (0.0, limit));
    hit.is_some_and(|hit| hit.t > 0.0 && hit.t <= limit)
}

/// The four-lane solver of `object` and its (c, e1, e2), where it is a parallelogram the kernel
/// takes and `simd` proves the processor runs it.
#[inline(always)]
fn parallelogram_lanes(
    simd: Option<Avx2>,
    object: &PreparedObject,
) -> Option<(Parallelogram4<'_>, [&V3<f64>; 3])> {
    let Geometry::Parallelogram {
        corner,
        e1,
        e2,
        lanes,
        ..
    } = &object.geometry
    else {
        return None;
    };
    let shape = [corner, e1, e2];
    Parallelogram4::new(simd, shape, lanes.as_ref()?).map(|solver| (solver, shape))
}

/// [`any_hit`] testing every object in turn, without the index.
pub(super) fn any_of_each_object(
    prepared: &Prepared,
    ray: &Ray,
    range: (f64, f64),
    stats: &mut Stats,
) -> bool {
    (0..prepared.objects.len()).any(|index| object_blocks(prepared, index, ray, range, stats))
}

/// True when object `index` is hit in (t_min, t_max): a mesh taking the crack-free test asks its
/// BVH's any-hit walk ([`Bvh::occluded`], the same decisions as the nearest-hit test's), lone
/// triangles in world space from t_min = 0 take the crack-free test directly (as a packet's rays
/// do; through the general search, a lone shadow ray's triangle test took 368 instructions),
/// a parallelogram from t_min = 0 seed 001's solver in lanes, anything else the first hit
/// [`object_hit_between`] finds.
fn object_blocks(
    prepared: &Prepared,
    index: usize,
    ray: &Ray,
    (t_min, t_max): (f64, f64),
    stats: &mut Stats,
) -> bool {
    let object = &prepared.objects[index];
    if let Geometry::Triangles { bvh: Some(bvh), .. } = &object.geometry
        && crack_free_applies(prepared, object)
    {
        let local = in_object_space(object, ray, prepared.bug, stats);
        let (boxes, triangles) = (&mut stats.box_tests, &mut stats.triangle_tests);
        return bvh.occluded(prepared.simd, &local, (t_min, t_max), boxes, triangles);
    }
    // Lone triangles in the world's space (the Cornell box's walls, a floor's triangle): the
    // crack-free test on each, as `lone_triangles_block` tests a packet's rays.
    if t_min == 0.0
        && let Some(triangles) = lone_world_triangles(prepared, object)
    {
        return ShearedRay::new(&ray.origin, &ray.dir)
            .is_some_and(|sheared| lone_triangle_blocks(triangles, &sheared, t_max, stats));
    }
    // The largest float below t_max: the same open interval.
    let range = (t_min, t_max.next_down());
    if t_min == 0.0
        && test_bug(prepared).is_none()
        && let Some((solver, shape)) = parallelogram_lanes(prepared.simd, object)
    {
        // Seed 001's solver, one lane of its kernel in scalar f64: no prefilter, no norms.
        let local = in_object_space(object, ray, prepared.bug, stats);
        stats.parallelogram_tests += 1;
        let blocks = solver.blocks_one(&local, t_max);
        return blocks.unwrap_or_else(|| blocks_alone(shape, *local, t_max));
    }
    object_hit_between(prepared, index, *ray, range, Find::Any, stats).is_some()
}

/// Object `index`'s nearest hit in (t_min, t_max], or with [`Find::Any`] the first one found.
fn object_hit_between(
    prepared: &Prepared,
    index: usize,
    ray: Ray,
    (t_min, t_max): (f64, f64),
    find: Find,
    stats: &mut Stats,
) -> Option<Hit> {
    let object = &prepared.objects[index];
    let local = to_object_space(object, ray, prepared.bug, stats);
    let in_range = |t: f64| t > t_min && t <= t_max;
    match &object.geometry {
        Geometry::Triangles { triangles, bvh } => {
            let hit = triangles_between(
                prepared,
                object,
                (triangles, bvh.as_deref()),
                local,
                (t_min, t_max),
                find,
                stats,
            )?;
            Some(Hit {
                object: index,
                ..hit
            })
        }
        Geometry::Parallelogram { corner, e1, e2, .. } => {
            stats.parallelogram_tests += 1;
            let hit = test_parallelogram([corner, e1, e2], prepared.bug, local, (t_min, t_max))?;
            in_range(hit.t).then_some(Hit::parallelogram(index, hit))
        }
    }
}

/// The nearest (or, with [`Find::Any`], the first found) of an object's triangles hit in
/// (t_min, t_max], in object space; its `object` is left 0.
fn triangles_between(
    prepared: &Prepared,
    object: &PreparedObject,
    (triangles, bvh): (&[PreparedTriangle], Option<&Bvh>),
    ray: Ray,
    (t_min, t_max): (f64, f64),
    find: Find,
    stats: &mut Stats,
) -> Option<Hit> {
    let crack_free = crack_free_applies(prepared, object);
    if crack_free
        && find == Find::Nearest
        && let Some(bvh) = bvh
    {
        let (primitive, hit) = bvh.nearest_crack_free(
            prepared.simd,
            &ray,
            (t_min, t_max),
            &mut stats.box_tests,
            &mut stats.triangle_tests,
        )?;
        return Some(Hit::triangle(0, primitive, hit));
    }
    let sheared = if crack_free {
        ShearedRay::new(&ray.origin, &ray.dir)
    } else {
        None
    };
    if crack_free && sheared.is_none() {
        return None;
    }
    let mut search = Search {
        triangles,
        sheared,
        method: prepared.method_for(object),
        bug: prepared.bug,
        ray,
        find,
        range: (t_min, t_max),
        best: None,
        tests: 0,
    };
    let culls = !matches!(prepared.bug, Some(Bug::AndForOr | Bug::VInsteadOfSum));
    match bvh.filter(|_| culls) {
        Some(bvh) => bvh.traverse(&ray, t_min, t_max, &mut stats.box_tests, |primitive| {
            search.consider(primitive)
        }),
        None => {
            for primitive in 0..triangles.len() {
                // −∞: an any-hit query found its hit.
                if search.consider(primitive) == Some(f64::NEG_INFINITY) {
                    break;
                }
            }
        }
    }
    stats.triangle_tests += search.tests;
    search.best
}

/// The search through an object's triangles, one at a time: how each is decided, the best hit so
/// far and the tests made. (A struct with always-inlined methods rather than closures: LLVM
/// stopped inlining the closures into the one-triangle loop when the meshes became shared, 6% more
/// instructions on the shadows scene.)
struct Search<'a> {
    triangles: &'a [PreparedTriangle],
    /// The crack-free test's sheared ray, when that test applies.
    sheared: Option<ShearedRay>,
    method: Method,
    bug: Option<Bug>,
    ray: Ray,
    find: Find,
    range: (f64, f64),
    best: Option<Hit>,
    tests: u64,
}

impl Search<'_> {
    /// Triangle `triangle`'s hit past t_min.
    #[inline(always)]
    fn decide(&self, triangle: &PreparedTriangle) -> Option<TriangleHit> {
        let t_min = self.range.0;
        match &self.sheared {
            Some(sheared) => sheared.intersect(&triangle.vertices, t_min),
            None => {
                test_triangle(triangle, self.method, self.bug, self.ray).filter(|h| h.t > t_min)
            }
        }
    }

    /// Tests triangle `primitive`: the t up to which the walk goes on (−∞: an any-hit query is
    /// done, as no box can be nearer), or `None` when it changed nothing.
    #[inline(always)]
    fn consider(&mut self, primitive: usize) -> Option<f64> {
        if self.find == Find::Any && self.best.is_some() {
            return None;
        }
        self.tests += 1;
        let limit = self.best.map_or(self.range.1, |b| b.t);
        let hit = self
            .decide(&self.triangles[primitive])
            .filter(|h| h.t <= limit)?;
        offer(&mut self.best, Hit::triangle(0, primitive, hit));
        Some(if self.find == Find::Any {
            f64::NEG_INFINITY
        } else {
            hit.t
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::parallelogram::{RayParallelogram, solve};
    use rand::SeedableRng;

    /// The prefilter never skips a ray the solver finds inside (α, β in [0, 1]): random
    /// parallelograms, rays aimed at points just inside and just outside their edges, and grazing.
    #[test]
    fn the_parallelogram_prefilter_skips_only_misses() {
        let mut random = rand_pcg::Pcg64::seed_from_u64(1);
        let mut skipped = 0;
        for i in 0..50_000 {
            let [corner, e1, e2, origin, mut dir] =
                crate::geometry::parallelogram::lean::random_ray_near_edges(&mut random, 1e-12);
            if i % 10 == 0 {
                // Nearly in the plane.
                let n = crate::math::linalg::cross(&e1, &e2);
                dir = std::array::from_fn(|k| e1[k] + 1e-9 * n[k]);
            }
            let problem = RayParallelogram::new([corner, e1, e2, origin, dir]);
            let range = (f64::NEG_INFINITY, f64::INFINITY);
            if !surely_outside([&corner, &e1, &e2], &origin, &dir, range) {
                continue;
            }
            skipped += 1;
            if let Some([alpha, beta, _]) = solve(&problem, &mut ()).alpha_beta_t {
                let inside = (0.0..=1.0).contains(&alpha) && (0.0..=1.0).contains(&beta);
                assert!(
                    !inside,
                    "{problem:?}: skipped, but ({alpha}, {beta}) is inside"
                );
            }
        }
        assert!(skipped > 10_000, "{skipped}");
    }

    /// A cull test's case: (c, e1, e2, o, d), the problem, whether the solver finds it inside, its t.
    pub(super) type ScaledCase = ([V3<f64>; 5], RayParallelogram<f64>, bool, f64);

    /// Case `i` of the cull tests: a ray near a random parallelogram's edges and corners, reversed
    /// every third case, everything scaled by 1e-150 to 1e150; the numbers, the problem, whether
    /// seed 001's solver finds it inside and its t (`None` where the solver finds no t).
    pub(super) fn scaled_case(random: &mut rand_pcg::Pcg64, i: usize) -> Option<ScaledCase> {
        let [corner, e1, e2, origin, mut dir] =
            crate::geometry::parallelogram::lean::random_ray_near_edges(random, 1e-12);
        if i.is_multiple_of(3) {
            dir = dir.map(|x| -x);
        }
        let scale = [1e-150, 1e-20, 1e20, 1e150, 1.0, 1.0][i % 6];
        let (corner, e1) = (corner.map(|x| x * scale), e1.map(|x| x * scale));
        let (origin, dir) = (origin.map(|x| x * scale), dir.map(|x| x * scale));
        let problem = RayParallelogram::new([corner, e1, e2, origin, dir]);
        let [alpha, beta, t] = solve(&problem, &mut ()).alpha_beta_t?;
        let inside = (0.0..=1.0).contains(&alpha) && (0.0..=1.0).contains(&beta);
        Some(([corner, e1, e2, origin, dir], problem, inside, t))
    }

    /// The prefilter's cull by t never skips a ray whose hit would be kept (inside, t ≤ t_max): rays
    /// near edges and corners, in front and behind, scaled far from 1, with t_max at the solver's
    /// t, a few ulps either side, a relative 1e-9 either side, 1e-5 before, and anywhere; and it
    /// does cull, also just before t.
    #[test]
    fn the_parallelogram_cull_skips_only_hits_beyond_t_max() {
        use rand::Rng;
        let mut random = rand_pcg::Pcg64::seed_from_u64(12);
        let (mut culled, mut near_misses) = (0, 0);
        for i in 0..200_000 {
            let Some(([corner, e1, e2, origin, dir], problem, inside, t)) =
                scaled_case(&mut random, i)
            else {
                continue;
            };
            let t_max = match random.random_range(0..8) {
                0 => t,
                1 => t.next_up(),
                2 => t.next_down(),
                3 => t * (1.0 + 1e-9),
                4 => t * (1.0 - 1e-9),
                5 => t * (1.0 - 1e-5),
                6 => random.random_range(0.0..1.0) * t.abs(),
                _ => random.random_range(-1.0..1.0) * 10.0,
            };
            if !surely_outside(
                [&corner, &e1, &e2],
                &origin,
                &dir,
                (f64::NEG_INFINITY, t_max),
            ) {
                continue;
            }
            let kept = inside && t <= t_max;
            assert!(
                !kept,
                "{problem:?}: culled at t_max {t_max}, but t {t} is kept"
            );
            culled += inside as usize;
            near_misses += (inside && t_max >= t * (1.0 - 1e-5) && t > 0.0) as usize;
        }
        assert!(
            culled > 5_000 && near_misses > 500,
            "{culled} {near_misses}"
        );
    }
}

#[cfg(test)]
mod before_tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    /// The cull by t_min never skips a ray whose hit would be kept (inside, t > t_min): rays near
    /// edges and corners, in front and behind, scaled far from 1, with t_min at the solver's t, a
    /// few ulps either side, a relative 1e-9 either side, and anywhere; and it culls the rays that
    /// leave a parallelogram by a millionth, as a shadow ray does.
    #[test]
    fn the_parallelogram_cull_skips_only_hits_before_t_min() {
        let mut random = rand_pcg::Pcg64::seed_from_u64(21);
        let mut culled = 0;
        for i in 0..200_000 {
            let Some(([corner, e1, e2, origin, dir], problem, inside, t)) =
                super::tests::scaled_case(&mut random, i)
            else {
                continue;
            };
            let t_min = match random.random_range(0..7) {
                0 => t,
                1 => t.next_up(),
                2 => t.next_down(),
                3 => t * (1.0 + 1e-9),
                4 => t * (1.0 - 1e-9),
                5 => t + 1e-6 * t.abs(),
                _ => random.random_range(-1.0..1.0) * 10.0,
            };
            let range = (t_min, f64::INFINITY);
            if surely_outside([&corner, &e1, &e2], &origin, &dir, range) {
                let kept = inside && t > t_min;
                assert!(
                    !kept,
                    "{problem:?}: culled at t_min {t_min}, but t {t} is kept"
                );
            }
        }
        // Rays leaving a parallelogram from a millionth above it, as the tracer's do.
        for _ in 0..10_000 {
            let [corner, e1, e2, _, _] =
                crate::geometry::parallelogram::lean::random_ray_near_edges(&mut random, 1e-12);
            let n = unit(crate::math::linalg::cross(&e1, &e2));
            let (a, b) = (random.random_range(0.0..1.0), random.random_range(0.0..1.0));
            let origin = std::array::from_fn(|k| corner[k] + a * e1[k] + b * e2[k] + 1e-6 * n[k]);
            let dir: V3<f64> =
                std::array::from_fn(|k| n[k] + random.random_range(-0.5..0.5) * (e1[k] + e2[k]));
            if dot3(&dir, &n) > 0.1 {
                culled += usize::from(surely_outside(
                    [&corner, &e1, &e2],
                    &origin,
                    &dir,
                    (0.0, f64::INFINITY),
                ));
            }
        }
        assert!(culled > 5_000, "{culled}");
    }

    fn dot3(a: &V3<f64>, b: &V3<f64>) -> f64 {
        crate::math::linalg::dot(a, b)
    }
}

#[cfg(test)]
mod packet_tests {
    use super::*;
    use crate::render::loading::assets::Embedded;
    use crate::scene::{Problem, Scene};

    /// A mesh in front of two floors, one of them turned, stretched and moved (its rays go into its
    /// space before the four-ray kernel), seen from above and from below the floors.
    fn floors(camera_z: f64) -> Prepared {
        let text = format!(
            r#"(title: "t", note: "n", problem: Render((
                width: 64, height: 48,
                camera: Pinhole(position: (0.3, -5.0, {camera_z}), target: (0.0, 0.5, 0.3), fov_y: 50.0),
                objects: [
                    (shape: Mesh(obj: "meshes/octasphere.obj"),
                     transform: (translate: (0.0, 0.8, 0.6), scale: (1.6, 0.6, 0.9))),
                    (shape: Parallelogram(corner: (-3.0, -2.0, 0.0), e1: (6.0, 0.0, 0.0), e2: (0.0, 5.0, 0.0))),
                    (shape: Parallelogram(corner: (-1.0, -1.0, 0.0), e1: (2.0, 0.0, 0.0), e2: (0.5, 2.0, 0.0)),
                     transform: (translate: (0.5, 0.5, 0.4), rotate: (20.0, 0.0, 30.0), scale: (1.5, 0.7, 1.0))),
                ],
                effects: ["coverage"],
            )))"#
        );
        let Problem::Render(scene) = Scene::from_ron(&text, "floors.ron").unwrap().problem else {
            panic!("not a render scene");
        };
        Prepared::new(&scene, &Embedded).expect("the scene prepares")
    }

    /// Casts each pixel's ray in packets of sixteen along its row and alone, asks that the packet
    /// find the very hit the ray alone finds (object, triangle, and the bits of t, β and γ), and
    /// returns the lone rays' hits, each packet's work counted in `packet_stats` and the lone
    /// rays' in `single_stats`.
    fn packets_against_alone(
        prepared: &Prepared,
        packet_stats: &mut Stats,
        single_stats: &mut Stats,
    ) -> Vec<Option<Hit>> {
        let bits = |h: Option<Hit>| {
            h.map(|h| {
                let coordinates = h.coordinates().map(f64::to_bits);
                (h.object, h.primitive, h.t.to_bits(), coordinates)
            })
        };
        let mut alone = Vec::new();
        for row in 0..prepared.height {
            for start in (0..prepared.width).step_by(16) {
                let rays: [Ray; 16] = std::array::from_fn(|k| prepared.ray(row, start + k));
                let mut packet = [None; 16];
                nearest_hits(prepared, &rays, packet_stats, &mut packet);
                for (k, ray) in rays.iter().enumerate() {
                    let single = nearest_hit(prepared, *ray, single_stats);
                    let pixel = (row, start + k);
                    assert_eq!(bits(packet[k]), bits(single), "pixel {pixel:?}");
                    alone.push(single);
                }
            }
        }
        alone
    }

    /// Packets of 16 rays, whose parallelograms go four rays at a time through the AVX2 kernel, find
    /// the very hits (bits included) and test the parallelograms as often as one ray at a time;
    /// they skip the mesh where no ray of theirs meets its box.
    #[test]
    fn packets_hit_floors_as_one_ray_at_a_time() {
        let (mut floor_hits, mut turned_hits) = (0, 0);
        for camera_z in [2.0, -1.5] {
            let prepared = floors(camera_z);
            let (mut packet_stats, mut single_stats) = (Stats::default(), Stats::default());
            let hits = packets_against_alone(&prepared, &mut packet_stats, &mut single_stats);
            for hit in hits.into_iter().flatten() {
                floor_hits += usize::from(hit.object == 1);
                turned_hits += usize::from(hit.object == 2);
            }
            assert_eq!(
                packet_stats.parallelogram_tests,
                single_stats.parallelogram_tests
            );
            // The rays alone move into the mesh's space each; a packet none of whose rays meets
            // the mesh's box skips it. The turned floor's rays are moved either way.
            let floor_moves = packet_stats.parallelogram_tests / 2;
            assert!(
                packet_stats.transforms < single_stats.transforms
                    && packet_stats.transforms >= floor_moves,
                "{} moves in packets, {} alone",
                packet_stats.transforms,
                single_stats.transforms
            );
        }
        assert!(
            floor_hits > 600 && turned_hits > 50,
            "{floor_hits} {turned_hits}"
        );
    }

    /// Runs of every length from 0 to 40 (whole packets, and tails cast alone or padded with the
    /// last ray's copies): each ray's hit is the one it finds alone, bits included.
    #[test]
    fn runs_of_every_length_find_what_each_ray_finds_alone() {
        let prepared = floors(2.0);
        let bits = |h: Option<Hit>| h.map(|h| (h.object, h.primitive, h.t.to_bits()));
        let row = prepared.height / 2;
        let rays: Vec<Ray> = (0..40).map(|k| prepared.ray(row, 12 + k)).collect();
        let alone: Vec<_> = rays
            .iter()
            .map(|ray| {
                nearest_hit_between(&prepared, *ray, (0.0, f64::INFINITY), &mut Stats::default())
            })
            .collect();
        assert!(alone.iter().filter(|hit| hit.is_some()).count() > 30);
        for n in 0..=rays.len() {
            let together = nearest_hits_of_each(&prepared, &rays[..n], &mut Stats::default());
            let expected: Vec<_> = alone[..n].iter().copied().map(bits).collect();
            let found: Vec<_> = together.into_iter().map(bits).collect();
            assert_eq!(found, expected, "a run of {n}");
        }
    }

    /// A flattened mesh lying just above a floor, listed after it: the floor's hit, found first,
    /// is each packet ray's range when the mesh's box is tested, and the mesh's hits lie within a
    /// few thousandths of it. Packets find the very hits the rays alone find (a culling range cut
    /// short by a hundredth loses the mesh).
    #[test]
    fn a_mesh_just_before_a_floor_is_not_culled() {
        let text = r#"(title: "t", note: "n", problem: Render((
            width: 48, height: 32,
            camera: Pinhole(position: (0.2, -4.0, 3.0), target: (0.0, 0.0, 0.0), fov_y: 40.0),
            objects: [
                (shape: Parallelogram(corner: (-3.0, -3.0, 0.0), e1: (6.0, 0.0, 0.0), e2: (0.0, 6.0, 0.0))),
                (shape: Mesh(obj: "meshes/octasphere.obj"),
                 transform: (translate: (0.0, 0.0, 0.0111), scale: (1.2, 1.0, 0.01))),
            ],
            effects: ["coverage"],
        )))"#;
        let Problem::Render(scene) = Scene::from_ron(text, "flat.ron").unwrap().problem else {
            panic!("not a render scene");
        };
        let prepared = Prepared::new(&scene, &Embedded).expect("the scene prepares");
        let (mut packet_stats, mut single_stats) = (Stats::default(), Stats::default());
        let hits = packets_against_alone(&prepared, &mut packet_stats, &mut single_stats);
        let mesh_hits = hits.iter().flatten().filter(|hit| hit.object == 1).count();
        assert!(mesh_hits > 150, "{mesh_hits} hits on the mesh");
    }

    /// A lone triangle (no hierarchy, in world space) with the crack-free test, which packets take
    /// a triangle against four rays at a time: the very hits of the rays alone (bits included),
    /// and as many triangle tests. Three scenes: the one-light scene seen through a wide lens; a
    /// large triangle seen along the diagonal between the x and y axes, so that the rays of a
    /// packet do not all share their sheared axes (those that differ from the first go one at a
    /// time); and a triangle of size 10⁻¹⁵⁰ around the middle pixel's ray, whose edge functions'
    /// products are too small for the four-lane test (it hands the lanes back to the one-ray
    /// test, which finds that ray's hit).
    #[test]
    fn lone_triangles_hit_four_rays_at_a_time_as_one_ray_at_a_time() {
        let scene = |(width, height): (usize, usize), camera: &str, vertices: &str, floor: bool| {
            let floor = match floor {
                true => {
                    "(shape: Parallelogram(corner: (-3.0, -3.0, 0.0), e1: (6.0, 0.0, 0.0), e2: (0.0, 6.0, 0.0))),"
                }
                false => "",
            };
            let text = format!(
                r#"(title: "t", note: "n", problem: Render((
                    width: {width}, height: {height},
                    camera: {camera},
                    method: Some("watertight"),
                    objects: [{floor} (shape: Triangle(vertices: {vertices}))],
                    effects: ["coverage"],
                )))"#
            );
            let Problem::Render(scene) = Scene::from_ron(&text, "lone.ron").unwrap().problem else {
                panic!("not a render scene");
            };
            Prepared::new(&scene, &Embedded).expect("the scene prepares")
        };
        let wide = scene(
            (48, 32),
            "Pinhole(position: (0.0, -2.0, 2.0), target: (0.0, 0.0, 0.5), fov_y: 100.0)",
            "((-0.8, -0.5, 1.0), (0.8, -0.5, 1.0), (0.0, 0.8, 1.0))",
            true,
        );
        let diagonal = scene(
            (48, 32),
            "Pinhole(position: (0.0, 0.0, 0.0), target: (1.0, 1.0, 0.0), fov_y: 60.0)",
            "((6.0, -1.0, -5.0), (-1.0, 6.0, -5.0), (2.5, 2.5, 5.0))",
            false,
        );
        let tiny = scene(
            (49, 33),
            "Pinhole(position: (0.0, 0.0, 0.0), target: (0.0, 1.0, 0.0), fov_y: 60.0)",
            "((-1e-150, 1.0, -1e-150), (1e-150, 1.0, -1e-150), (0.0, 1.0, 1e-150))",
            false,
        );
        // Packets of the diagonal view whose rays' sheared axes differ.
        let mixed = (0..diagonal.height)
            .flat_map(|row| {
                (0..diagonal.width)
                    .step_by(16)
                    .map(move |start| (row, start))
            })
            .filter(|&(row, start)| {
                let axes: Vec<_> = (start..start + 16)
                    .filter_map(|column| {
                        let ray = diagonal.ray(row, column);
                        ShearedRay::new(&ray.origin, &ray.dir).map(|sheared| sheared.parts().1)
                    })
                    .collect();
                axes.windows(2).any(|pair| pair[0] != pair[1])
            })
            .count();
        assert!(mixed >= 10, "{mixed} packets of mixed axes");
        let triangle = |prepared: &Prepared| prepared.objects.len() - 1;
        for (prepared, least) in [(&wide, 10), (&diagonal, 1000), (&tiny, 1)] {
            let (mut packet_stats, mut single_stats) = (Stats::default(), Stats::default());
            let hits = packets_against_alone(prepared, &mut packet_stats, &mut single_stats);
            let on_triangle = hits
                .iter()
                .flatten()
                .filter(|hit| hit.object == triangle(prepared))
                .count();
            assert!(on_triangle >= least, "{on_triangle} hits on the triangle");
            assert_eq!(packet_stats.triangle_tests, single_stats.triangle_tests);
        }
    }

    /// A floor and a turned floor block a shadow ray (0 < t < t_max) as the one-ray solver's first
    /// hit in (0, the float below t_max] says, whether the ray goes alone (one scalar lane)
    /// or sixteen at a time: rays from random points and from points on the floor (t exactly 0),
    /// t_max at the solver's own t, either side of it, or anywhere.
    #[test]
    fn shadow_rays_meet_floors_as_the_one_ray_solver_says() {
        use rand::{Rng, SeedableRng};
        let prepared = floors(2.0);
        let mut random = rand_pcg::Pcg64::seed_from_u64(43);
        let mut stats = Stats::default();
        let mut blocked_count = 0;
        for i in 0..2_000 {
            let rays: [Ray; TOGETHER] = std::array::from_fn(|r| {
                let mut origin: V3<f64> = std::array::from_fn(|_| random.random_range(-2.5..2.5));
                if (i + r) % 3 == 0 {
                    origin[2] = 0.0;
                }
                let dir = std::array::from_fn(|_| random.random_range(-1.0..1.0));
                Ray::new(origin, dir)
            });
            for index in [1, 2] {
                let first_t = |ray: Ray, stats: &mut Stats| {
                    let range = (0.0, f64::INFINITY);
                    object_hit_between(&prepared, index, ray, range, Find::Any, stats).map(|h| h.t)
                };
                let t_max: [f64; TOGETHER] = std::array::from_fn(|r| {
                    let t = first_t(rays[r], &mut stats).unwrap_or(1.0);
                    match random.random_range(0..5) {
                        0 => t,
                        1 => t.next_up(),
                        2 => t.next_down(),
                        3 => f64::INFINITY,
                        _ => random.random_range(0.0..4.0),
                    }
                });
                let taking = random.random::<u32>() & 0xffff;
                let mut expected = 0;
                for (r, ray) in rays.iter().enumerate() {
                    let range = (0.0, t_max[r].next_down());
                    let one_ray =
                        object_hit_between(&prepared, index, *ray, range, Find::Any, &mut stats);
                    let alone = object_blocks(&prepared, index, ray, (0.0, t_max[r]), &mut stats);
                    assert_eq!(
                        alone,
                        one_ray.is_some(),
                        "{i} {index} {r}: {ray:?} {}",
                        t_max[r]
                    );
                    expected |= u32::from(alone) << r;
                }
                let mut sheared = [None; TOGETHER];
                let tested = ((&rays, taking), &mut sheared);
                let together = objects_block(&prepared, index, tested, &t_max, &mut stats);
                assert_eq!(together, expected & taking, "{i} {index}");
                blocked_count += expected.count_ones();
            }
        }
        assert!(blocked_count > 3_000, "{blocked_count}");
    }
}
