//! Seed 002 in symbols: the ray–triangle system M X = Y with the coordinates as variables (ax … dz),
//! Cramer's determinants expanded as polynomials, then the notebook's advice followed through: merge
//! the common terms, step by step, to the cross and dot products Möller–Trumbore computes.
//!
//! Every identity of the derivation is checked, not asserted: both sides are expanded and compared as
//! polynomials, and evaluated in exact arithmetic on the scene's own numbers.

use std::collections::BTreeMap;
use std::fmt::Write;

use crate::geometry::Precision;
use crate::math::exact::Exact;
use crate::trace::{Payload, Step, Symbolic, Trace};

/// The fifteen coordinates, in seed 002's order.
pub const VARIABLES: [&str; 15] = [
    "ax", "ay", "az", "bx", "by", "bz", "cx", "cy", "cz", "lx", "ly", "lz", "dx", "dy", "dz",
];

/// A monomial: the exponent of each variable.
type Monomial = [u8; 15];

/// A polynomial with integer coefficients in the fifteen coordinates.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Poly(BTreeMap<Monomial, i64>);

impl Poly {
    /// The variable with this index into [`VARIABLES`].
    pub fn var(index: usize) -> Poly {
        let mut monomial = [0; 15];
        monomial[index] = 1;
        Poly(BTreeMap::from([(monomial, 1)]))
    }

    fn add_term(&mut self, monomial: Monomial, coefficient: i64) {
        let entry = self.0.entry(monomial).or_insert(0);
        *entry += coefficient;
        if *entry == 0 {
            self.0.remove(&monomial);
        }
    }

    /// The sum.
    pub fn add(&self, other: &Poly) -> Poly {
        let mut sum = self.clone();
        for (m, c) in &other.0 {
            sum.add_term(*m, *c);
        }
        sum
    }

    /// The difference.
    pub fn sub(&self, other: &Poly) -> Poly {
        self.add(&other.neg())
    }

    /// The negation.
    pub fn neg(&self) -> Poly {
        Poly(self.0.iter().map(|(m, c)| (*m, -c)).collect())
    }

    /// The product.
    pub fn mul(&self, other: &Poly) -> Poly {
        let mut product = Poly::default();
        for (ma, ca) in &self.0 {
            for (mb, cb) in &other.0 {
                let monomial: Monomial = std::array::from_fn(|i| ma[i] + mb[i]);
                product.add_term(monomial, ca * cb);
            }
        }
        product
    }

    /// How many terms it has.
    pub fn terms(&self) -> usize {
        self.0.len()
    }

    /// Multiplications to evaluate it term by term as written: degree − 1 per term (and one more for
    /// a coefficient other than ±1).
    pub fn multiplications(&self) -> usize {
        self.0
            .iter()
            .map(|(m, c)| {
                let degree: usize = m.iter().map(|e| *e as usize).sum();
                degree.saturating_sub(1) + usize::from(c.abs() != 1)
            })
            .sum()
    }

    /// Its value at `values` (one per variable), exactly.
    pub fn eval(&self, values: &[Exact; 15]) -> Exact {
        let mut sum = Exact::from_int(0);
        for (monomial, coefficient) in &self.0 {
            let mut term = Exact::from_int(*coefficient);
            for (i, e) in monomial.iter().enumerate() {
                for _ in 0..*e {
                    term = term * values[i].clone();
                }
            }
            sum = sum + term;
        }
        sum
    }

    /// Plain text, as seed 002's notebook prints it: `ax*by*dz - ax*bz*dy + …`.
    pub fn text(&self) -> String {
        self.render(|name| name.to_string(), "*")
    }

    /// LaTeX: `a_{x} b_{y} d_{z} - …`.
    pub fn latex(&self) -> String {
        self.render(
            |name| {
                let (letter, axis) = name.split_at(1);
                format!("{letter}_{{{axis}}}")
            },
            " ",
        )
    }

    fn render(&self, name: impl Fn(&str) -> String, times: &str) -> String {
        if self.0.is_empty() {
            return "0".into();
        }
        let mut out = String::new();
        // Highest degree first, then in the variables' order.
        let mut terms: Vec<(&Monomial, &i64)> = self.0.iter().collect();
        terms.sort_by_key(|(m, _)| {
            let degree: u8 = m.iter().sum();
            (std::cmp::Reverse(degree), std::cmp::Reverse(**m))
        });
        for (i, (monomial, coefficient)) in terms.into_iter().enumerate() {
            let sign = if *coefficient < 0 { "-" } else { "+" };
            if i == 0 {
                if *coefficient < 0 {
                    out.push('-');
                }
            } else {
                let _ = write!(out, " {sign} ");
            }
            let mut factors: Vec<String> = Vec::new();
            if coefficient.abs() != 1 {
                factors.push(coefficient.abs().to_string());
            }
            for (v, e) in monomial.iter().enumerate() {
                for _ in 0..*e {
                    factors.push(name(VARIABLES[v]));
                }
            }
            if factors.is_empty() {
                factors.push("1".into());
            }
            out.push_str(&factors.join(times));
        }
        out
    }
}

/// A 3-vector of polynomials.
type Vec3 = [Poly; 3];

fn point(first: usize) -> Vec3 {
    std::array::from_fn(|i| Poly::var(first + i))
}

fn minus(a: &Vec3, b: &Vec3) -> Vec3 {
    std::array::from_fn(|i| a[i].sub(&b[i]))
}

fn cross(a: &Vec3, b: &Vec3) -> Vec3 {
    [
        a[1].mul(&b[2]).sub(&a[2].mul(&b[1])),
        a[2].mul(&b[0]).sub(&a[0].mul(&b[2])),
        a[0].mul(&b[1]).sub(&a[1].mul(&b[0])),
    ]
}

fn dot(a: &Vec3, b: &Vec3) -> Poly {
    a[0].mul(&b[0]).add(&a[1].mul(&b[1])).add(&a[2].mul(&b[2]))
}

/// The determinant of the matrix with these columns, by cofactors along the first row.
fn det(columns: [&Vec3; 3]) -> Poly {
    let m = |row: usize, col: usize| &columns[col][row];
    let minor = |r1: usize, c1: usize, r2: usize, c2: usize| {
        m(r1, c1).mul(m(r2, c2)).sub(&m(r1, c2).mul(m(r2, c1)))
    };
    m(0, 0)
        .mul(&minor(1, 1, 2, 2))
        .sub(&m(0, 1).mul(&minor(1, 0, 2, 2)))
        .add(&m(0, 2).mul(&minor(1, 0, 2, 1)))
}

/// The symbols of the system: E1 = A−B, E2 = A−C, D and T = A−L (Y).
struct System {
    e1: Vec3,
    e2: Vec3,
    d: Vec3,
    t: Vec3,
}

impl System {
    fn new() -> System {
        let (a, b, c, l, d) = (point(0), point(3), point(6), point(9), point(12));
        System {
            e1: minus(&a, &b),
            e2: minus(&a, &c),
            d,
            t: minus(&a, &l),
        }
    }
}

/// One identity of the merge, checked both ways.
#[derive(Clone, Debug, PartialEq)]
pub struct Identity {
    /// Plain text, e.g. `|M| = (A−B)·q`.
    pub text: String,
    /// Whether both sides expand to the same polynomial.
    pub holds_symbolically: bool,
    /// Both sides on the scene's numbers, exactly (when numbers were given).
    pub on_the_scene: Option<(Exact, Exact)>,
}

/// The trace of seed 002's derivation, the scene's numbers (A, B, C, L, D) used to check each
/// identity when given.
pub fn trace(scene: Option<&[[Exact; 3]; 5]>) -> Trace {
    let system = System::new();
    let values: Option<[Exact; 15]> =
        scene.map(|s| std::array::from_fn(|i| s[i / 3][i % 3].clone()));
    let mut trace = Trace::new("triangle-symbolic", Precision::Exact);
    let (e1, e2, d, t) = (&system.e1, &system.e2, &system.d, &system.t);
    // A matrix as its named columns, a line each: a line wraps on a narrow panel, a matrix row of
    // three expressions would not.
    let columns = |name: &str, c: [(&str, &Vec3); 3]| -> Vec<String> {
        let names: Vec<&str> = c.iter().map(|(n, _)| *n).collect();
        let mut lines = vec![format!("{name} = [{}], with", names.join(" | "))];
        for (column, v) in c {
            let parts: Vec<String> = v.iter().map(Poly::text).collect();
            lines.push(format!("{column} = ({})", parts.join(", ")));
        }
        lines
    };
    let matrix_latex = |c: [&Vec3; 3]| -> String {
        let rows: Vec<String> = (0..3)
            .map(|row| {
                c.iter()
                    .map(|col| col[row].latex())
                    .collect::<Vec<_>>()
                    .join(" & ")
            })
            .collect();
        format!(
            "\\begin{{bmatrix}} {} \\end{{bmatrix}}",
            rows.join(" \\\\ ")
        )
    };
    let mut lines = columns("M", [("A−B", e1), ("A−C", e2), ("D", d)]);
    lines.push("X = (β, γ, t)".into());
    let y: Vec<String> = t.iter().map(Poly::text).collect();
    lines.push(format!("Y = A − L = ({})", y.join(", ")));
    trace.steps.push(step(
        "system",
        "The system M X = Y in symbols",
        "L + tD = A + β(B−A) + γ(C−A) with every coordinate a symbol, as seed 002 declares them.",
        lines,
        format!(
            "M = {}, \\quad Y = \\begin{{bmatrix}} {} \\end{{bmatrix}}",
            matrix_latex([e1, e2, d]),
            t.iter().map(Poly::latex).collect::<Vec<_>>().join(" \\\\ ")
        ),
    ));
    let matrices = [
        ("M1", "M_1", [("Y", t), ("A−C", e2), ("D", d)]),
        ("M2", "M_2", [("A−B", e1), ("Y", t), ("D", d)]),
        ("M3", "M_3", [("A−B", e1), ("A−C", e2), ("Y", t)]),
    ];
    for (name, latex, cols) in matrices {
        trace.steps.push(step(
            name,
            &format!("{name}: Y in column {}", &name[1..]),
            "Cramer's rule: replace one column of M by Y = A − L.",
            columns(name, cols),
            format!("{latex} = {}", matrix_latex(cols.map(|(_, v)| v))),
        ));
    }
    let dets = [
        ("det_M", "|M|", "|M|", det([e1, e2, d])),
        ("det_M1", "|M1|", "|M_1|", det([t, e2, d])),
        ("det_M2", "|M2|", "|M_2|", det([e1, t, d])),
        ("det_M3", "|M3|", "|M_3|", det([e1, e2, t])),
    ];
    let mut brute = 0;
    for (id, name, latex, poly) in &dets {
        brute += poly.multiplications();
        trace.steps.push(step(
            id,
            &format!("{name} expanded"),
            &format!(
                "The determinant as a polynomial: {} terms, {} multiplications as written.",
                poly.terms(),
                poly.multiplications()
            ),
            vec![format!("{name} = {}", poly.text())],
            format!("{latex} = {}", poly.latex()),
        ));
    }
    for (id, symbol, latex, det_id) in [
        ("beta", "β", "\\beta", "|M1|"),
        ("gamma", "γ", "\\gamma", "|M2|"),
        ("t", "t", "t", "|M3|"),
    ] {
        trace.steps.push(step(
            id,
            &format!("{symbol} = {det_id} / |M|"),
            "Seed 002 divides the expanded determinants; |M| should be computed once.",
            vec![format!("{symbol} = {det_id} / |M|")],
            format!(
                "{latex} = \\frac{{{}}}{{|M|}}",
                det_id
                    .replace("M1", "M_1")
                    .replace("M2", "M_2")
                    .replace("M3", "M_3")
            ),
        ));
    }
    // Merging common terms: shared edge vectors, then two shared cross products.
    let q = cross(e2, d);
    let r = cross(e1, t);
    let identities: [(&str, &str, &str, Poly, Poly); 4] = [
        (
            "merge_M",
            "|M| = (A−B)·q, with q = (A−C) × D",
            "|M| = (A-B)\\cdot q,\\quad q = (A-C)\\times D",
            dets[0].3.clone(),
            dot(e1, &q),
        ),
        (
            "merge_M1",
            "|M1| = (A−L)·q: the same q",
            "|M_1| = (A-L)\\cdot q",
            dets[1].3.clone(),
            dot(t, &q),
        ),
        (
            "merge_M2",
            "|M2| = D·r, with r = (A−B) × (A−L)",
            "|M_2| = D\\cdot r,\\quad r = (A-B)\\times(A-L)",
            dets[2].3.clone(),
            dot(d, &r),
        ),
        (
            "merge_M3",
            "|M3| = −(A−C)·r: the same r",
            "|M_3| = -(A-C)\\cdot r",
            dets[3].3.clone(),
            dot(e2, &r).neg(),
        ),
    ];
    for (id, text, latex, expanded, merged) in identities {
        let identity = check(text, &expanded, &merged, values.as_ref());
        let mut lines = vec![text.to_string()];
        lines.push(if identity.holds_symbolically {
            "✓ both sides expand to the same polynomial".to_string()
        } else {
            "✗ the two sides differ as polynomials".to_string()
        });
        if let Some((left, right)) = &identity.on_the_scene {
            let mark = if left == right { "✓" } else { "✗" };
            lines.push(format!(
                "{mark} on this scene: {} = {}",
                left.display(),
                right.display()
            ));
        }
        let title = format!("Merge: {}", text.split([',', ':']).next().unwrap_or(text));
        trace.steps.push(Step::new(
            id,
            title,
            "Seed 002's advice: compute each shared piece once.",
            Payload::Symbolic(Symbolic {
                lines,
                latex: latex.to_string(),
                holds: Some(
                    identity.holds_symbolically
                        && identity.on_the_scene.as_ref().is_none_or(|(l, r)| l == r),
                ),
            }),
        ));
    }
    // Multiplications after merging: q and r (6 each), four dot products (3 each); one division for
    // 1/|M| then three products, against three divisions before.
    let merged = 6 + 6 + 4 * 3;
    let cofactor = 4 * 9;
    trace.steps.push(step(
        "count",
        "What merging saves",
        "Multiplications for the four determinants (the subtractions A−B, A−C, A−L are shared by all).",
        vec![
            format!("expanded polynomials as written: {brute}"),
            format!("cofactor expansion, four 3x3 determinants: {cofactor}"),
            format!(
                "merged (q, r and four dot products, as Möller–Trumbore computes them): {merged}"
            ),
        ],
        format!(
            "\\text{{expanded: }} {brute}, \\quad \\text{{cofactors: }} {cofactor}, \\quad \\text{{merged: }} {merged}"
        ),
    ));
    trace
}

fn check(text: &str, expanded: &Poly, merged: &Poly, values: Option<&[Exact; 15]>) -> Identity {
    Identity {
        text: text.to_string(),
        holds_symbolically: expanded == merged,
        on_the_scene: values.map(|v| (expanded.eval(v), merged.eval(v))),
    }
}

fn step(id: &str, title: &str, explanation: &str, lines: Vec<String>, latex: String) -> Step {
    Step::new(
        id,
        title,
        explanation,
        Payload::Symbolic(Symbolic {
            lines,
            latex,
            holds: None,
        }),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::triangle::RayTriangle;
    use crate::geometry::{Lecture, TriangleLecture};
    use rand::{Rng, SeedableRng};

    fn random_scene(rng: &mut rand_pcg::Pcg64) -> [[Exact; 3]; 5] {
        std::array::from_fn(|_| {
            std::array::from_fn(|_| {
                Exact::ratio(rng.random_range(-20..=20), rng.random_range(1..=7)).unwrap()
            })
        })
    }

    #[test]
    fn the_symbolic_determinants_equal_the_exact_ones() {
        let system = System::new();
        let (e1, e2, d, t) = (&system.e1, &system.e2, &system.d, &system.t);
        let dets = [
            det([e1, e2, d]),
            det([t, e2, d]),
            det([e1, t, d]),
            det([e1, e2, t]),
        ];
        let mut rng = rand_pcg::Pcg64::seed_from_u64(2018);
        for _ in 0..50 {
            let scene = random_scene(&mut rng);
            let values: [Exact; 15] = std::array::from_fn(|i| scene[i / 3][i % 3].clone());
            let problem = RayTriangle::<Exact> {
                a: scene[0].clone(),
                b: scene[1].clone(),
                c: scene[2].clone(),
                origin: scene[3].clone(),
                dir: scene[4].clone(),
                t_min: Exact::from_int(0),
            };
            let (_, trace) = TriangleLecture::traced(&problem);
            for (poly, id) in dets.iter().zip(["det_M", "det_M1", "det_M2", "det_M3"]) {
                let Some(step) = trace.step(id) else {
                    continue; // a degenerate or parallel draw stops before |M1|
                };
                let crate::trace::Payload::Determinant(det) = &step.payload else {
                    panic!("{id} is a determinant");
                };
                let exact: Exact = det.value.exact.as_deref().unwrap().parse().unwrap();
                assert_eq!(poly.eval(&values), exact, "{id}");
            }
        }
    }

    #[test]
    fn every_merge_identity_holds() {
        let trace = trace(None);
        let merges: Vec<_> = trace
            .steps
            .iter()
            .filter(|s| s.id.starts_with("merge_"))
            .collect();
        assert_eq!(merges.len(), 4);
        for step in merges {
            let Payload::Symbolic(s) = &step.payload else {
                panic!("{} is symbolic", step.id)
            };
            assert_eq!(s.holds, Some(true), "{}: {:?}", step.id, s.lines);
        }
        // On random scenes, both sides agree in exact arithmetic too.
        let mut rng = rand_pcg::Pcg64::seed_from_u64(20);
        for _ in 0..20 {
            let scene = random_scene(&mut rng);
            for step in trace_steps(&scene) {
                assert_eq!(step, Some(true));
            }
        }
        // A wrong identity is caught.
        let system = System::new();
        let wrong = check(
            "|M3| = (A−C)·r",
            &det([&system.e1, &system.e2, &system.t]),
            &dot(&system.e2, &cross(&system.e1, &system.t)),
            None,
        );
        assert!(!wrong.holds_symbolically);
    }

    fn trace_steps(scene: &[[Exact; 3]; 5]) -> Vec<Option<bool>> {
        trace(Some(scene))
            .steps
            .iter()
            .filter(|s| s.id.starts_with("merge_"))
            .map(|s| match &s.payload {
                Payload::Symbolic(s) => s.holds,
                _ => None,
            })
            .collect()
    }

    #[test]
    fn polynomials_print_as_the_notebook_does() {
        let (ax, by) = (Poly::var(0), Poly::var(4));
        let p = ax.mul(&by).sub(&by).add(&by.mul(&by).mul(&Poly::var(14)));
        assert_eq!(p.text(), "by*by*dz + ax*by - by");
        assert_eq!(p.latex(), "b_{y} b_{y} d_{z} + a_{x} b_{y} - b_{y}");
        assert_eq!(p.multiplications(), 2 + 1);
        assert_eq!(Poly::default().text(), "0");
    }
}
