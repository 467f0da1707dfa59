//! Fuzzing of scene files (issue 19, "Hardening"): a property-based generator (proptest) of
//! random and mutated scenes, run through parse, model build and a small solve for a bounded
//! time: no panic, no abort, no non-finite output.
//!
//! Three cases in four are a scene shipped in `assets/scenes/*.toml`, read as a TOML tree, with
//! one to four random mutations: a number pushed to an extreme (0, −0, ±1, 10⁻³⁰⁰, 5·10⁻³²⁴,
//! 10³⁰⁰, ±f64::MAX, NaN, ±inf, 2³², i64::MAX, i64::MIN, −10⁶, negated, scaled by 10⁶ or 10⁻⁶),
//! nudged (×2, ×½, ×10, ×0.1, ×1.01, ×−1), a key dropped, a value's type swapped, a size
//! (`cells`, `layers`, `resolution`) blown up, an array entry duplicated, an array emptied, a
//! string replaced by an odd one. One case in four is a random scene ([`random_scene`]: boxes,
//! balls, hollow balls and explicit meshes, some of their cells collapsed or inverted, under
//! random materials, supports, loads, gravity, obstacles and solver settings) with up to three
//! of the same mutations. The tree is then written back as TOML text.
//!
//! - `mutated_scenes_parse_and_build_without_panic` (in process, many cases; the hands of the
//!   shipped scenes at resolution 0.5, which builds in a quarter of the time): `Scene::parse`
//!   and, when it accepts the text, `Model::build`. No panic; an error's text is non-empty and
//!   names the file. Sizes the program would accept but that make a big mesh (more than
//!   [`IN_PROCESS_MAX_CELLS`] elements, or a hand finer than resolution 1.25) are not built here
//!   (counted as too big): they are the subprocess test's, under its memory limit.
//! - `mutated_scenes_solve_or_fail_cleanly` (fewer cases): the shipped scenes shrunk first
//!   (hands at resolution 0.5, balls with 6 cells, boxes with 3 per axis) so that an unmutated
//!   one solves in about a second, then mutated (or a random scene), written to a file and
//!   solved by the real command line, `prehensile solve FILE --out DIR`, in a child process with
//!   a time limit and (on Linux) a 4 GiB address-space limit, two at a time. It must exit with
//!   code 0, 1 or 2 (a keyframe the solver could not follow: the frames up to where it stopped
//!   are written) — not a signal (abort, segfault), not 101 (a panic) — with no "panicked at"
//!   on stderr; a run killed at the time limit is counted, not failed. With code 0 or 2, every
//!   file written has only finite numbers (VTU/PVD attribute values and `DataArray` tokens, OBJ
//!   coordinates, every JSON value: the report leaves absent optional fields out, so a `null`
//!   there is a NaN or an infinity that serde_json wrote as null); with code 1, nothing is
//!   written to `--out`.
//!
//! Both use a fixed seed (`FUZZ_SEED` overrides it, `FUZZ_CASES` / `FUZZ_SOLVE_CASES` the
//! numbers of cases, for a longer run by hand: `FUZZ_SEED=7 FUZZ_CASES=3000 cargo test --release
//! --test suite fuzz_scenes:: -- --nocapture`). Both print what their cases did (`--nocapture`)
//! and write it to `$CARGO_TARGET_TMPDIR/fuzz_scenes/summary-*.txt`; both fail if too few cases got
//! through (the fuzz cannot pass vacuously). A failing case is shrunk to fewer, simpler
//! mutations; its scene text is printed and written under
//! `$CARGO_TARGET_TMPDIR/fuzz_scenes/findings/`.
//!
//! Failures found by this file are minimised and kept in [`FOUND`]:
//! `found_scenes_solve_or_fail_cleanly` solves each of them as a subprocess case, under the same
//! property, and fails if src panics or aborts on one again:
//! - a panic at `src/fem/solve.rs` (index out of bounds: faer's `NonPositivePivot` index, counted
//!   from 1, used to index the permutation) on auxetic balls (ν = −0.99) under the nonlinear
//!   tier — fixed in d7f4d90 (now refused, exit 1);
//! - an abort (memory allocation failed, SIGABRT) under the 4 GiB address-space limit in the
//!   nonlinear statics of a refined hollow ball of 130 cells — fixed in 1f1ed8c (refused by the
//!   memory estimate, exit 1).

use crate::common;

use common::limited::{signal, solve_limited, toml_files, trimmed, written, Ending};
use prehensile::model::Model;
use prehensile::scene::{Scene, Shape};
use proptest::prelude::*;
use proptest::sample::{select, Index};
use proptest::strategy::{BoxedStrategy, ValueTree};
use proptest::test_runner::{Config, RngAlgorithm, RngSeed, TestCaseError, TestError, TestRunner};
use std::collections::BTreeSet;
use std::fs;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};
use toml::{Table, Value};

/// The name the scene text goes by in errors (in process) and on disk (subprocess).
const FILE: &str = "fuzz.toml";

/// Default seed of both tests.
const SEED: u64 = 0x5EED_F022_1989;

/// In-process cases.
const CASES: u32 = 400;

/// Subprocess cases.
const SOLVE_CASES: usize = 40;

/// Largest mesh built in process (elements); bigger ones that the program accepts are left to
/// the subprocess test.
const IN_PROCESS_MAX_CELLS: usize = 200_000;

/// The program's own cap on a shape's elements (`src/model/shapes.rs`).
const PROGRAM_MAX_CELLS: usize = 5_000_000;

/// Longest a subprocess case may run before it is killed (then counted as a timeout).
const TIME_LIMIT: Duration = Duration::from_secs(10);

/// Address space allowed to a subprocess case (Linux only).
const ADDRESS_SPACE_LIMIT: u64 = 4 << 30;

/// Subprocess cases run at once.
const WORKERS: usize = 2;

/// Longest time spent shrinking the failing subprocess cases, all together.
const SHRINK_BUDGET: Duration = Duration::from_secs(120);

/// The tests of this file take turns: each is timed for a 2-core machine on its own.
static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());

fn env_number<T: std::str::FromStr>(name: &str, default: T) -> T {
    std::env::var(name)
        .ok()
        .and_then(|v| v.trim().parse().ok())
        .unwrap_or(default)
}

// ---------------------------------------------------------------------------------------------
// The shipped scenes.

/// A shipped scene: its file name and its TOML tree.
#[derive(Clone, Debug)]
struct Base {
    name: String,
    tree: Table,
}

/// `assets/scenes/*.toml`, sorted by name.
fn shipped_scenes() -> Vec<Base> {
    let files = toml_files("assets/scenes");
    assert!(
        files.len() >= 5,
        "assets/scenes holds {} scenes",
        files.len()
    );
    files
        .iter()
        .map(|p| {
            let text = fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            let tree: Table = text
                .parse()
                .unwrap_or_else(|e| panic!("{}: not TOML: {e}", p.display()));
            Base {
                name: p.file_name().unwrap().to_string_lossy().to_string(),
                tree,
            }
        })
        .collect()
}

/// The scene made small: hands at resolution 0.5 (a quarter of the time to build at 1); unless
/// `hands_only`, balls with 6 cells and boxes with at most 3 cells per axis too, so that it solves
/// in about a second (the shipped selections still select nodes).
fn shrunk(mut base: Base, hands_only: bool) -> Base {
    if let Some(Value::Array(bodies)) = base.tree.get_mut("body") {
        for body in bodies {
            let Some(Value::Table(shape)) = body.get_mut("shape") else {
                continue;
            };
            for (kind, params) in shape.iter_mut() {
                let Value::Table(params) = params else {
                    continue;
                };
                match kind.as_str() {
                    "hand" => {
                        params.insert("resolution".into(), Value::Float(0.5));
                    }
                    _ if hands_only => {}
                    "sphere" | "shell" => {
                        if let Some(Value::Integer(c)) = params.get_mut("cells") {
                            *c = (*c).min(6);
                        }
                    }
                    "box" => {
                        if let Some(Value::Array(cells)) = params.get_mut("cells") {
                            for c in cells {
                                if let Value::Integer(c) = c {
                                    *c = (*c).min(3);
                                }
                            }
                        }
                    }
                    _ => {}
                }
            }
        }
    }
    base
}

// ---------------------------------------------------------------------------------------------
// Mutations.

/// A number put in place of another.
#[derive(Clone, Debug)]
enum Extreme {
    /// This value.
    Set(Value),
    /// The number negated (i64::MIN becomes i64::MAX).
    Negate,
    /// The number times this factor (an integer stays an integer, saturating).
    Scale(f64),
}

/// A value of another type.
#[derive(Clone, Copy, Debug)]
enum Kind {
    Text,
    Integer,
    Float,
    Boolean,
    EmptyArray,
    NumberArray,
    TextArray,
    EmptyTable,
    Table,
    Datetime,
}

const KINDS: [Kind; 10] = [
    Kind::Text,
    Kind::Integer,
    Kind::Float,
    Kind::Boolean,
    Kind::EmptyArray,
    Kind::NumberArray,
    Kind::TextArray,
    Kind::EmptyTable,
    Kind::Table,
    Kind::Datetime,
];

impl Kind {
    fn value(self) -> Value {
        match self {
            Kind::Text => Value::String("fuzz".into()),
            Kind::Integer => Value::Integer(7),
            Kind::Float => Value::Float(0.25),
            Kind::Boolean => Value::Boolean(true),
            Kind::EmptyArray => Value::Array(vec![]),
            Kind::NumberArray => Value::Array(vec![
                Value::Float(1.0),
                Value::Float(2.0),
                Value::Float(3.0),
            ]),
            Kind::TextArray => Value::Array(vec![Value::String("x-".into())]),
            Kind::EmptyTable => Value::Table(Table::new()),
            Kind::Table => {
                let mut t = Table::new();
                t.insert("x".into(), Value::Integer(1));
                Value::Table(t)
            }
            Kind::Datetime => Value::Datetime("1989-07-01T12:00:00Z".parse().expect("datetime")),
        }
    }
}

/// One change to a scene tree. `at` picks among the nodes the mutation applies to (in a fixed
/// depth-first order), after the earlier mutations; one with no node to apply to does nothing.
/// `keep_type`: an integer put where a float was is written as a float and the reverse (a
/// float put in an integer's place is cast: NaN to 0, ±inf to i64::MAX/MIN), so that more
/// cases get past the parser into the model's checks and the solver.
#[derive(Clone, Debug)]
enum Mutation {
    /// A number (integer or float, anywhere) pushed to an extreme.
    Extreme {
        at: Index,
        to: Extreme,
        keep_type: bool,
    },
    /// A number scaled by a moderate factor (an integer stays one, rounded).
    Nudge { at: Index, factor: f64 },
    /// A key of a table removed.
    Drop { at: Index },
    /// A value (anywhere below the top) replaced by one of another type.
    Swap { at: Index, to: Kind },
    /// A size (`cells`, an entry of a box's `cells`, `layers`, `resolution`) made large.
    BlowUp {
        at: Index,
        to: Value,
        keep_type: bool,
    },
    /// An array's entry repeated after itself; `tables`: only arrays of tables (bodies,
    /// constraints, keyframes...), not vectors.
    Duplicate {
        at: Index,
        entry: Index,
        tables: bool,
    },
    /// An array emptied.
    Empty { at: Index, tables: bool },
    /// A string replaced by an odd one.
    Text { at: Index, to: String },
}

/// Where a case's scene comes from.
#[derive(Clone, Debug)]
enum Source {
    /// The shipped scene of this index.
    Shipped(usize),
    /// A scene generated from scratch ([`random_scene`]).
    Random(Table),
}

/// A case: a scene and the mutations applied to it in order.
#[derive(Clone, Debug)]
struct Case {
    source: Source,
    mutations: Vec<Mutation>,
}

fn extremes() -> Vec<Extreme> {
    use Extreme::*;
    vec![
        Set(Value::Integer(0)),
        Set(Value::Float(-0.0)),
        Set(Value::Integer(-1)),
        Set(Value::Integer(1)),
        Set(Value::Float(1e-300)),
        Set(Value::Float(5e-324)),
        Set(Value::Float(1e300)),
        Set(Value::Float(f64::MAX)),
        Set(Value::Float(f64::MIN)),
        Set(Value::Float(f64::NAN)),
        Set(Value::Float(f64::INFINITY)),
        Set(Value::Float(f64::NEG_INFINITY)),
        Set(Value::Integer(4_294_967_296)),
        Set(Value::Integer(i64::MAX)),
        Set(Value::Integer(i64::MIN)),
        Set(Value::Float(-1e6)),
        Negate,
        Scale(1e6),
        Scale(1e-6),
    ]
}

/// Sizes: a few the program accepts but that make big meshes (a ball of 170 cells is 4.9 M
/// elements, a hand at resolution 4 is 64 times the default one), and more that it must refuse
/// by its size checks before allocating.
fn huge_sizes() -> Vec<Value> {
    vec![
        Value::Integer(64),
        Value::Float(2.0),
        Value::Float(4.0),
        Value::Integer(170),
        Value::Integer(171),
        Value::Integer(1000),
        Value::Integer(65_536),
        Value::Integer(1_000_000),
        Value::Integer(4_294_967_296),
        Value::Integer(i64::MAX),
        Value::Float(4.5),
        Value::Float(1e6),
        Value::Float(1e300),
    ]
}

fn odd_strings() -> Vec<String> {
    vec![
        String::new(),
        " ".into(),
        "nan".into(),
        "inf".into(),
        "1e300".into(),
        "x-".into(),
        "index.distal".into(),
        "\u{0}\u{7f}\u{202e}".into(),
        "Ünïcödé 漢字 🖐".into(),
        "a".repeat(10_000),
    ]
}

fn mutation() -> BoxedStrategy<Mutation> {
    let keep_type = || proptest::bool::weighted(0.75);
    let tables = || proptest::bool::weighted(0.7);
    prop_oneof![
        5 => (any::<Index>(), select(extremes()), keep_type())
            .prop_map(|(at, to, keep_type)| Mutation::Extreme { at, to, keep_type }),
        3 => (any::<Index>(), select(vec![2.0, 0.5, 10.0, 0.1, 1.01, -1.0]))
            .prop_map(|(at, factor)| Mutation::Nudge { at, factor }),
        2 => any::<Index>().prop_map(|at| Mutation::Drop { at }),
        1 => (any::<Index>(), select(KINDS.to_vec())).prop_map(|(at, to)| Mutation::Swap { at, to }),
        2 => (any::<Index>(), select(huge_sizes()), keep_type())
            .prop_map(|(at, to, keep_type)| Mutation::BlowUp { at, to, keep_type }),
        1 => (any::<Index>(), any::<Index>(), tables())
            .prop_map(|(at, entry, tables)| Mutation::Duplicate { at, entry, tables }),
        1 => (any::<Index>(), tables()).prop_map(|(at, tables)| Mutation::Empty { at, tables }),
        1 => (any::<Index>(), select(odd_strings())).prop_map(|(at, to)| Mutation::Text { at, to }),
    ]
    .boxed()
}

/// `v` with the type of `target` where both are numbers (see [`Mutation`], `keep_type`).
fn like(target: &Value, v: Value) -> Value {
    match (target, v) {
        (Value::Integer(_), Value::Float(f)) => Value::Integer(f as i64),
        (Value::Float(_), Value::Integer(i)) => Value::Float(i as f64),
        (_, v) => v,
    }
}

/// An array of tables (`[[body]]`...), not a vector of numbers.
fn of_tables(v: &Value) -> bool {
    matches!(v, Value::Array(a) if a.first().is_some_and(|x| x.is_table()))
}

/// `shipped` cases in `shipped + random` mutate a shipped scene (one to four mutations), the
/// others a random scene (none to two).
fn case_strategy(bases: usize, shipped: u32, random: u32) -> BoxedStrategy<Case> {
    prop_oneof![
        shipped => (0..bases, prop::collection::vec(mutation(), 1..=4)).prop_map(
            |(base, mutations)| Case {
                source: Source::Shipped(base),
                mutations,
            }
        ),
        random => (random_scene(), prop::collection::vec(mutation(), 0..=2)).prop_map(
            |(tree, mutations)| Case {
                source: Source::Random(tree),
                mutations,
            }
        ),
    ]
    .boxed()
}

// ---------------------------------------------------------------------------------------------
// Random scenes: one or two bodies (box, solid ball, hollow ball or an explicit mesh, some of
// its cells collapsed or turned inside out) of size `l` about the origin, one or two materials
// from soft to stiff, constraints and loads on selections made for that geometry (the bottom
// and top slabs, all nodes, a point, the outer or inner surface, a face), gravity, obstacles and
// solver settings. Many are refused (a body left free to move, a selection that selects
// nothing); the rest solve with values no shipped scene has.

fn float(x: f64) -> Value {
    Value::Float(x)
}

fn vector(x: [f64; 3]) -> Value {
    Value::Array(x.iter().map(|&v| Value::Float(v)).collect())
}

fn table<const N: usize>(entries: [(&str, Value); N]) -> Value {
    Value::Table(
        entries
            .into_iter()
            .map(|(k, v)| (k.to_string(), v))
            .collect(),
    )
}

fn text(s: &str) -> Value {
    Value::String(s.to_string())
}

/// A shape of size `l` about the origin.
#[derive(Clone, Debug)]
enum RandomShape {
    Box {
        cells: [i64; 3],
    },
    Sphere {
        cells: i64,
        refine: bool,
    },
    Shell {
        cells: i64,
        layers: i64,
        refine: bool,
    },
    /// `cubes` cubes in a row along x; the first cell changed by `variant`.
    Mesh {
        cubes: usize,
        variant: usize,
    },
}

impl RandomShape {
    fn value(&self, l: f64) -> Value {
        let h = l / 2.0;
        match self {
            RandomShape::Box { cells } => table([(
                "box",
                table([
                    ("min", vector([-h, -h, -h])),
                    ("max", vector([h, h, h])),
                    (
                        "cells",
                        Value::Array(cells.iter().map(|&c| Value::Integer(c)).collect()),
                    ),
                ]),
            )]),
            RandomShape::Sphere { cells, refine } => {
                let mut t = Table::new();
                t.insert("center".into(), vector([0.0; 3]));
                t.insert("radius".into(), float(h));
                t.insert("cells".into(), Value::Integer(*cells));
                if *refine {
                    t.insert(
                        "refine".into(),
                        table([("toward", vector([0.0, 0.0, l])), ("size", float(h / 8.0))]),
                    );
                }
                table([("sphere", Value::Table(t))])
            }
            RandomShape::Shell {
                cells,
                layers,
                refine,
            } => {
                let mut t = Table::new();
                t.insert("center".into(), vector([0.0; 3]));
                t.insert("inner_radius".into(), float(0.8 * h));
                t.insert("outer_radius".into(), float(h));
                t.insert("cells".into(), Value::Integer(*cells));
                t.insert("layers".into(), Value::Integer(*layers));
                if *refine {
                    t.insert(
                        "refine".into(),
                        table([("toward", vector([0.0, 0.0, l])), ("size", float(h / 16.0))]),
                    );
                }
                table([("shell", Value::Table(t))])
            }
            RandomShape::Mesh { cubes, variant } => {
                // Nodes in slices x = const, each slice (y, z) in the order (-,-), (+,-), (+,+),
                // (-,+); cube c joins slices c and c + 1 in VTK order (z- face first).
                let n = *cubes;
                let w = l / n as f64;
                let mut nodes = Vec::new();
                for i in 0..=n {
                    let x = -h + w * i as f64;
                    for (y, z) in [(-h, -h), (h, -h), (h, h), (-h, h)] {
                        nodes.push(vector([x, y, z]));
                    }
                }
                let cell = |c: usize| -> [i64; 8] {
                    let (a, b) = (4 * c as i64, 4 * c as i64 + 4);
                    // z- face: (a0, b0, b1, a1), z+ face: (a3, b3, b2, a2).
                    [a, b, b + 1, a + 1, a + 3, b + 3, b + 2, a + 2]
                };
                let mut cells: Vec<[i64; 8]> = (0..n).map(cell).collect();
                let first = cells[0];
                let f = |i: usize| first[i];
                cells[0] = match variant {
                    0 => first,
                    // A prism and a tetrahedron, as collapsed hexahedra.
                    1 => [f(0), f(1), f(2), f(2), f(4), f(5), f(6), f(6)],
                    2 => [f(0), f(1), f(2), f(2), f(4), f(4), f(4), f(4)],
                    // Turned inside out, flattened, and a node index past the end.
                    3 => [f(4), f(5), f(6), f(7), f(0), f(1), f(2), f(3)],
                    4 => [f(0), f(1), f(2), f(3), f(0), f(1), f(2), f(3)],
                    _ => [f(0), f(1), f(2), f(3), f(4), f(5), f(6), nodes.len() as i64],
                };
                let cells = cells
                    .iter()
                    .map(|c| Value::Array(c.iter().map(|&i| Value::Integer(i)).collect()))
                    .collect();
                table([(
                    "mesh",
                    table([
                        ("nodes", Value::Array(nodes)),
                        ("cells", Value::Array(cells)),
                    ]),
                )])
            }
        }
    }
}

fn random_shape() -> BoxedStrategy<RandomShape> {
    prop_oneof![
        prop::array::uniform3(1i64..=4).prop_map(|cells| RandomShape::Box { cells }),
        (1i64..=6, proptest::bool::weighted(0.3))
            .prop_map(|(cells, refine)| RandomShape::Sphere { cells, refine }),
        (1i64..=6, 1i64..=3, proptest::bool::weighted(0.3)).prop_map(|(cells, layers, refine)| {
            RandomShape::Shell {
                cells,
                layers,
                refine,
            }
        }),
        (1usize..=3, prop_oneof![3 => Just(0usize), 1 => 1usize..=5])
            .prop_map(|(cubes, variant)| RandomShape::Mesh { cubes, variant }),
    ]
    .boxed()
}

/// A selection: `where` for a geometry of size `l` about the origin.
fn selection(which: usize, l: f64) -> Value {
    let big = 2.0 * l;
    match which {
        // The slabs below z = -l/4 and above l/4: the lowest and highest nodes of a box, a mesh
        // or a ball of one cell or more.
        0 => table([(
            "box",
            table([
                ("min", vector([-big, -big, -big])),
                ("max", vector([big, big, -0.25 * l])),
            ]),
        )]),
        1 => table([(
            "box",
            table([
                ("min", vector([-big, -big, 0.25 * l])),
                ("max", vector([big, big, big])),
            ]),
        )]),
        2 => table([(
            "box",
            table([("min", vector([-big; 3])), ("max", vector([big; 3]))]),
        )]),
        3 => table([("point", vector([0.0, 0.0, l]))]),
        4 => table([("surface", text("outer"))]),
        5 => table([("surface", text("inner"))]),
        _ => table([("face", text("z-"))]),
    }
}

/// The materials' (Young's modulus, Poisson's ratio, density).
fn materials() -> impl Strategy<Value = Vec<(f64, f64, f64)>> {
    prop::collection::vec(
        (
            select(vec![1e6, 1e-3, 1.0, 5e4, 2e11, 1e13]),
            select(vec![0.3, -0.99, 0.0, 0.45, 0.499_999]),
            select(vec![1000.0, 0.0, 1e5]),
        ),
        1..=2,
    )
}

/// A constraint: (body, selection, displacement); mostly the top slab or a point, which any
/// shape has and the bottom slab's hold does not prescribe already.
fn constraint() -> impl Strategy<Value = (Index, usize, usize)> {
    let selection = prop_oneof![6 => select(vec![1usize, 3]), 1 => 0usize..7];
    (any::<Index>(), selection, 0usize..5)
}

/// A load: (body, selection, kind); mostly on the top slab, the outer surface or every node.
fn load() -> impl Strategy<Value = (Index, usize, usize)> {
    let selection = prop_oneof![6 => select(vec![1usize, 4, 2]), 1 => 0usize..7];
    (any::<Index>(), selection, 0usize..6)
}

fn random_scene() -> BoxedStrategy<Table> {
    (
        select(vec![1.0, 1e-3, 0.05, 1e3]),
        materials(),
        prop::collection::vec(
            (
                random_shape(),
                any::<Index>(),
                proptest::bool::weighted(0.85),
            ),
            1..=2,
        ),
        prop::collection::vec(constraint(), 0..=3),
        prop::collection::vec(load(), 0..=2),
        (0usize..3, 0usize..3, 0usize..6),
    )
        .prop_map(
            |(l, materials, bodies, constraints, loads, (gravity, obstacle, solver))| {
                let mut scene = Table::new();
                let names: Vec<String> = (0..materials.len()).map(|i| format!("m{i}")).collect();
                scene.insert(
                    "material".into(),
                    Value::Array(
                        materials
                            .iter()
                            .zip(&names)
                            .map(|(&(young, poisson, density), name)| {
                                table([
                                    ("name", text(name)),
                                    ("young", float(young)),
                                    ("poisson", float(poisson)),
                                    ("density", float(density)),
                                ])
                            })
                            .collect(),
                    ),
                );
                let body_names: Vec<String> = (0..bodies.len()).map(|i| format!("b{i}")).collect();
                scene.insert(
                    "body".into(),
                    Value::Array(
                        bodies
                            .iter()
                            .zip(&body_names)
                            .map(|((shape, material, _), name)| {
                                table([
                                    ("name", text(name)),
                                    ("material", text(&names[material.index(names.len())])),
                                    ("shape", shape.value(l)),
                                ])
                            })
                            .collect(),
                    ),
                );
                let body = |i: &Index| text(&body_names[i.index(body_names.len())]);
                let displacements = [
                    vector([0.0; 3]),
                    table([("z", float(-0.01 * l))]),
                    table([("x", float(0.0)), ("y", float(0.0))]),
                    vector([0.01 * l, 0.0, 0.0]),
                    table([("z", float(0.3 * l))]),
                ];
                // Most bodies are held at their bottom slab, so that they need no other
                // constraint to be solvable.
                let held = bodies
                    .iter()
                    .zip(&body_names)
                    .filter(|((_, _, held), _)| *held)
                    .map(|(_, name)| {
                        table([
                            ("name", text(&format!("{name} held"))),
                            ("body", text(name)),
                            ("where", selection(0, l)),
                            ("displacement", vector([0.0; 3])),
                        ])
                    });
                let others = constraints.iter().enumerate().map(|(i, (b, sel, d))| {
                    table([
                        ("name", text(&format!("c{i}"))),
                        ("body", body(b)),
                        ("where", selection(*sel, l)),
                        ("displacement", displacements[*d].clone()),
                    ])
                });
                scene.insert(
                    "constraint".into(),
                    Value::Array(held.chain(others).collect()),
                );
                let load_kinds = [
                    ("pressure", float(1e4)),
                    ("pressure", float(-1e5)),
                    ("force", vector([0.0, 0.0, -10.0])),
                    ("traction", vector([1e3, 0.0, 0.0])),
                    ("force", vector([0.0, 0.0, 0.0])),
                    ("pressure", float(3e4)),
                ];
                scene.insert(
                    "load".into(),
                    Value::Array(
                        loads
                            .iter()
                            .enumerate()
                            .map(|(i, (b, sel, k))| {
                                let (key, value) = load_kinds[*k].clone();
                                let mut t = Table::new();
                                t.insert("name".into(), text(&format!("l{i}")));
                                t.insert("body".into(), body(b));
                                t.insert("where".into(), selection(*sel, l));
                                t.insert(key.into(), value);
                                if *k == 5 {
                                    // A sealed gas cavity (refused unless the selection
                                    // encloses one).
                                    t.insert("gas".into(), Value::Boolean(true));
                                }
                                Value::Table(t)
                            })
                            .collect(),
                    ),
                );
                match gravity {
                    1 => {
                        scene.insert(
                            "world".into(),
                            table([("gravity", vector([0.0, 0.0, -9.81]))]),
                        );
                    }
                    2 => {
                        scene.insert(
                            "world".into(),
                            table([("gravity", vector([3e3, 0.0, -1e5]))]),
                        );
                    }
                    _ => {}
                }
                let obstacles = match obstacle {
                    1 => vec![table([
                        ("name", text("floor")),
                        (
                            "shape",
                            table([(
                                "plane",
                                table([
                                    ("point", vector([0.0, 0.0, -0.5 * l])),
                                    ("normal", vector([0.0, 0.0, 1.0])),
                                ]),
                            )]),
                        ),
                    ])],
                    2 => vec![table([
                        ("name", text("rigid ball")),
                        (
                            "shape",
                            table([(
                                "sphere",
                                table([
                                    ("center", vector([0.0, 0.0, 0.9 * l])),
                                    ("radius", float(0.45 * l)),
                                ]),
                            )]),
                        ),
                    ])],
                    _ => vec![],
                };
                if !obstacles.is_empty() {
                    scene.insert("obstacle".into(), Value::Array(obstacles));
                }
                let solver = match solver {
                    1 => Some(table([("tier", text("nonlinear"))])),
                    2 => Some(table([("element", text("incompatible_modes"))])),
                    3 => Some(table([
                        ("ordering", text("amd")),
                        ("max_memory", text("50 MB")),
                    ])),
                    4 => Some(table([
                        ("tier", text("nonlinear")),
                        ("volumetric", text("full")),
                    ])),
                    _ => None,
                };
                if let Some(solver) = solver {
                    scene.insert("solver".into(), solver);
                }
                scene.insert(
                    "probe".into(),
                    Value::Array(vec![table([
                        ("name", text("p")),
                        ("body", text(&body_names[0])),
                        ("point", vector([0.0, 0.0, 0.5 * l])),
                    ])]),
                );
                scene
            },
        )
        .boxed()
}

/// A step from a node to a child.
#[derive(Clone, Debug)]
enum Step {
    Key(String),
    At(usize),
}

/// A node of the tree: its path from the top, and the nearest key above it (its own key, or
/// for an array entry the array's).
struct Node {
    path: Vec<Step>,
    key: String,
}

/// Every node below the top, depth first.
fn nodes(top: &Table) -> Vec<Node> {
    fn walk(v: &Value, path: &mut Vec<Step>, key: &str, out: &mut Vec<Node>) {
        out.push(Node {
            path: path.clone(),
            key: key.to_string(),
        });
        match v {
            Value::Table(t) => {
                for (k, child) in t {
                    path.push(Step::Key(k.clone()));
                    walk(child, path, k, out);
                    path.pop();
                }
            }
            Value::Array(a) => {
                for (i, child) in a.iter().enumerate() {
                    path.push(Step::At(i));
                    walk(child, path, key, out);
                    path.pop();
                }
            }
            _ => {}
        }
    }
    let mut out = Vec::new();
    for (k, child) in top {
        let mut path = vec![Step::Key(k.clone())];
        walk(child, &mut path, k, &mut out);
    }
    out
}

fn node_mut<'a>(top: &'a mut Table, path: &[Step]) -> Option<&'a mut Value> {
    let (first, rest) = path.split_first()?;
    let Step::Key(k) = first else { return None };
    let mut v = top.get_mut(k)?;
    for step in rest {
        v = match (step, v) {
            (Step::Key(k), Value::Table(t)) => t.get_mut(k)?,
            (Step::At(i), Value::Array(a)) => a.get_mut(*i)?,
            _ => return None,
        };
    }
    Some(v)
}

fn node<'a>(top: &'a Table, path: &[Step]) -> Option<&'a Value> {
    let (first, rest) = path.split_first()?;
    let Step::Key(k) = first else { return None };
    let mut v = top.get(k)?;
    for step in rest {
        v = match (step, v) {
            (Step::Key(k), Value::Table(t)) => t.get(k)?,
            (Step::At(i), Value::Array(a)) => a.get(*i)?,
            _ => return None,
        };
    }
    Some(v)
}

/// `body[1].shape.shell.cells` for people.
fn dotted(path: &[Step]) -> String {
    let mut s = String::new();
    for step in path {
        match step {
            Step::Key(k) => {
                if !s.is_empty() {
                    s.push('.');
                }
                s.push_str(k);
            }
            Step::At(i) => s.push_str(&format!("[{i}]")),
        }
    }
    s
}

fn type_name(v: &Value) -> &'static str {
    match v {
        Value::String(_) => "string",
        Value::Integer(_) => "integer",
        Value::Float(_) => "float",
        Value::Boolean(_) => "boolean",
        Value::Datetime(_) => "datetime",
        Value::Array(_) => "array",
        Value::Table(_) => "table",
    }
}

fn short(v: &Value) -> String {
    let s = match v {
        Value::String(s) => format!("{s:?}"),
        other => other.to_string(),
    };
    if s.chars().count() > 40 {
        format!("{}…", s.chars().take(40).collect::<String>())
    } else {
        s
    }
}

/// Applies one mutation; what it did (None when it found nothing to apply to).
fn apply(tree: &mut Table, m: &Mutation) -> Option<String> {
    let all = nodes(tree);
    let pick = |at: &Index, keep: &dyn Fn(&Node, &Value) -> bool| -> Option<Vec<Step>> {
        let candidates: Vec<&Node> = all
            .iter()
            .filter(|n| node(tree, &n.path).is_some_and(|v| keep(n, v)))
            .collect();
        (!candidates.is_empty()).then(|| candidates[at.index(candidates.len())].path.clone())
    };
    let is_number = |v: &Value| matches!(v, Value::Integer(_) | Value::Float(_));
    match m {
        Mutation::Extreme { at, to, keep_type } => {
            let path = pick(at, &|_, v| is_number(v))?;
            let v = node_mut(tree, &path)?;
            let new = match (to, &*v) {
                (Extreme::Set(x), _) if *keep_type => like(v, x.clone()),
                (Extreme::Set(x), _) => x.clone(),
                (Extreme::Negate, Value::Integer(i)) => {
                    Value::Integer(i.checked_neg().unwrap_or(i64::MAX))
                }
                (Extreme::Negate, Value::Float(f)) => Value::Float(-f),
                (Extreme::Scale(k), Value::Integer(i)) => Value::Integer((*i as f64 * k) as i64),
                (Extreme::Scale(k), Value::Float(f)) => Value::Float(f * k),
                _ => return None,
            };
            let said = format!("{} = {} (was {})", dotted(&path), short(&new), short(v));
            *v = new;
            Some(said)
        }
        Mutation::Nudge { at, factor } => {
            let path = pick(at, &|_, v| is_number(v))?;
            let v = node_mut(tree, &path)?;
            let new = match &*v {
                Value::Integer(i) => Value::Integer((*i as f64 * factor).round() as i64),
                Value::Float(f) => Value::Float(f * factor),
                _ => return None,
            };
            let said = format!("{} = {} (was {})", dotted(&path), short(&new), short(v));
            *v = new;
            Some(said)
        }
        Mutation::Drop { at } => {
            let path = pick(at, &|n, _| matches!(n.path.last(), Some(Step::Key(_))))?;
            let (Some(Step::Key(k)), parent) = (path.last(), &path[..path.len() - 1]) else {
                return None;
            };
            let table = if parent.is_empty() {
                &mut *tree
            } else {
                match node_mut(tree, parent)? {
                    Value::Table(t) => t,
                    _ => return None,
                }
            };
            table.remove(k)?;
            Some(format!("{} dropped", dotted(&path)))
        }
        Mutation::Swap { at, to } => {
            let path = pick(at, &|_, _| true)?;
            let v = node_mut(tree, &path)?;
            // The first kind from `to` on whose type differs from the value's.
            let start = KINDS
                .iter()
                .position(|k| std::mem::discriminant(k) == std::mem::discriminant(to))?;
            let new = (0..KINDS.len())
                .map(|i| KINDS[(start + i) % KINDS.len()].value())
                .find(|x| type_name(x) != type_name(v))?;
            let said = format!(
                "{} = {} (was {} {})",
                dotted(&path),
                short(&new),
                type_name(v),
                short(v)
            );
            *v = new;
            Some(said)
        }
        Mutation::BlowUp { at, to, keep_type } => {
            let path = pick(at, &|n, v| {
                is_number(v) && matches!(n.key.as_str(), "cells" | "layers" | "resolution")
            })?;
            let v = node_mut(tree, &path)?;
            let new = if *keep_type {
                like(v, to.clone())
            } else {
                to.clone()
            };
            let said = format!("{} = {} (was {})", dotted(&path), short(&new), short(v));
            *v = new;
            Some(said)
        }
        Mutation::Duplicate { at, entry, tables } => {
            let path = pick(at, &|_, v| {
                matches!(v, Value::Array(a) if !a.is_empty()) && (!tables || of_tables(v))
            })?;
            let Value::Array(a) = node_mut(tree, &path)? else {
                return None;
            };
            let i = entry.index(a.len());
            let copy = a[i].clone();
            a.insert(i + 1, copy);
            Some(format!("{}[{i}] duplicated", dotted(&path)))
        }
        Mutation::Empty { at, tables } => {
            let path = pick(at, &|_, v| {
                matches!(v, Value::Array(a) if !a.is_empty()) && (!tables || of_tables(v))
            })?;
            let Value::Array(a) = node_mut(tree, &path)? else {
                return None;
            };
            a.clear();
            Some(format!("{} emptied", dotted(&path)))
        }
        Mutation::Text { at, to } => {
            let path = pick(at, &|_, v| matches!(v, Value::String(_)))?;
            let v = node_mut(tree, &path)?;
            let new = Value::String(to.clone());
            let said = format!("{} = {} (was {})", dotted(&path), short(&new), short(v));
            *v = new;
            Some(said)
        }
    }
}

/// The case's scene text (None where the TOML writer refuses the tree) and what was done.
fn render(bases: &[Base], case: &Case) -> (Option<String>, Vec<String>) {
    let (mut tree, mut done) = match &case.source {
        Source::Shipped(i) => (
            bases[*i].tree.clone(),
            vec![format!("from {}", bases[*i].name)],
        ),
        Source::Random(tree) => (tree.clone(), vec!["a random scene".to_string()]),
    };
    for m in &case.mutations {
        done.push(apply(&mut tree, m).unwrap_or_else(|| "(nothing to mutate)".into()));
    }
    (toml::to_string(&tree).ok(), done)
}

/// The case as a file: what was done as comments, then the text.
fn as_file(done: &[String], text: &str) -> String {
    let mut s: String = done.iter().map(|d| format!("# {d}\n")).collect();
    s.push('\n');
    s.push_str(text);
    s
}

fn panic_text(p: &(dyn std::any::Any + Send)) -> String {
    p.downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| p.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "(not a string)".into())
}

/// Prints `text` and writes it to `$CARGO_TARGET_TMPDIR/fuzz_scenes/summary-NAME.txt`.
fn write_summary(name: &str, text: &str) {
    println!("{text}");
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fuzz_scenes");
    let _ = fs::create_dir_all(&dir);
    let _ = fs::write(dir.join(format!("summary-{name}.txt")), format!("{text}\n"));
}

fn findings_dir() -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join("fuzz_scenes/findings")
}

fn record_finding(name: &str, contents: &str) -> PathBuf {
    let dir = findings_dir();
    fs::create_dir_all(&dir).expect("findings folder");
    let path = dir.join(name);
    fs::write(&path, contents).expect("write finding");
    path
}

// ---------------------------------------------------------------------------------------------
// In process: parse and build.

/// Why a scene is not built in process (a mesh the program accepts but that is big), if so.
fn too_big_in_process(scene: &Scene) -> Option<String> {
    let accepted_but_big =
        |n: Option<usize>| n.is_some_and(|n| n > IN_PROCESS_MAX_CELLS && n <= PROGRAM_MAX_CELLS);
    for body in &scene.body {
        let big = match &body.shape {
            Shape::Box { cells, .. } => {
                accepted_but_big(cells.iter().try_fold(1usize, |n, &c| n.checked_mul(c)))
            }
            Shape::Sphere { cells, refine, .. } => {
                // A refined ball grades finer toward a point: allow for many more cells.
                let n = cells.checked_pow(3);
                accepted_but_big(n) || (refine.is_some() && n.is_some_and(|n| n > 2_000))
            }
            Shape::Shell {
                cells,
                layers,
                refine,
                ..
            } => {
                let n = cells
                    .checked_mul(*cells)
                    .and_then(|n| n.checked_mul(*layers))
                    .and_then(|n| n.checked_mul(6));
                accepted_but_big(n) || (refine.is_some() && n.is_some_and(|n| n > 2_000))
            }
            Shape::Hand { resolution, .. } => *resolution > 1.25 && *resolution < 10.0,
            Shape::Mesh { .. } => false,
        };
        if big {
            return Some(format!("body {:?}: {:?}", body.name, body.shape));
        }
    }
    None
}

/// What the library made of a case.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum InProcess {
    ParseError,
    TooBig,
    BuildError,
    Built,
}

/// Checks an error's text: non-empty, naming the file.
fn check_error(stage: &str, e: &dyn std::fmt::Display) -> Result<(), String> {
    let text = e.to_string();
    if text.trim().is_empty() {
        return Err(format!("{stage} error with an empty text"));
    }
    if !text.contains(FILE) {
        return Err(format!("{stage} error does not name {FILE}: {text}"));
    }
    Ok(())
}

fn run_in_process(text: &str) -> Result<InProcess, String> {
    let parsed = catch_unwind(|| Scene::parse(text, FILE))
        .map_err(|p| format!("Scene::parse panicked: {}", panic_text(&*p)))?;
    let scene = match parsed {
        Err(e) => {
            check_error("parse", &e)?;
            return Ok(InProcess::ParseError);
        }
        Ok(scene) => scene,
    };
    if too_big_in_process(&scene).is_some() {
        return Ok(InProcess::TooBig);
    }
    let built = catch_unwind(AssertUnwindSafe(|| Model::build(&scene, FILE)))
        .map_err(|p| format!("Model::build panicked: {}", panic_text(&*p)))?;
    match built {
        Err(e) => {
            check_error("build", &e)?;
            Ok(InProcess::BuildError)
        }
        Ok(_) => Ok(InProcess::Built),
    }
}

fn runner(cases: u32, seed: u64) -> TestRunner {
    TestRunner::new(Config {
        cases,
        failure_persistence: None,
        rng_algorithm: RngAlgorithm::ChaCha,
        rng_seed: RngSeed::Fixed(seed),
        max_shrink_iters: 2_000,
        ..Config::default()
    })
}

#[test]
fn mutated_scenes_parse_and_build_without_panic() {
    let _turn = ONE_AT_A_TIME.lock().unwrap_or_else(|p| p.into_inner());
    let start = Instant::now();
    let bases: Vec<Base> = shipped_scenes()
        .into_iter()
        .map(|b| shrunk(b, true))
        .collect();
    let cases: u32 = env_number("FUZZ_CASES", CASES);
    let seed: u64 = env_number("FUZZ_SEED", SEED);
    let counts = Mutex::new(std::collections::BTreeMap::<String, usize>::new());
    let count = |what: &str| *counts.lock().unwrap().entry(what.to_string()).or_default() += 1;
    let slowest = Mutex::new((Duration::ZERO, String::new()));

    let result = runner(cases, seed).run(&case_strategy(bases.len(), 3, 1), |case| {
        let (text, done) = render(&bases, &case);
        let Some(text) = text else {
            count("unwritable");
            return Ok(());
        };
        let t = Instant::now();
        let outcome = run_in_process(&text);
        let took = t.elapsed();
        {
            let mut s = slowest.lock().unwrap();
            if took > s.0 {
                *s = (took, done.join("; "));
            }
        }
        match outcome {
            Ok(o) => {
                count(&format!("{o:?}"));
                Ok(())
            }
            Err(problem) => {
                count("FAILED");
                Err(TestCaseError::fail(format!(
                    "{problem}\n--- the scene ({FILE}) ---\n{}",
                    as_file(&done, &text)
                )))
            }
        }
    });

    let counts = counts.into_inner().unwrap();
    let get = |k: &str| counts.get(k).copied().unwrap_or(0);
    let (slow, slow_case) = slowest.into_inner().unwrap();
    write_summary(
        "in-process",
        &format!(
            "fuzz (in process, seed {seed:#x}, {cases} cases, {:.1} s): {} parse errors, {} \
             build errors, {} built, {} too big to build in process, {} not writable as TOML, {} \
             failed (shrinking included); slowest {:.2} s: {slow_case}",
            start.elapsed().as_secs_f64(),
            get("ParseError"),
            get("BuildError"),
            get("Built"),
            get("TooBig"),
            get("unwritable"),
            get("FAILED"),
            slow.as_secs_f64(),
        ),
    );

    if let Err(e) = result {
        let message = match e {
            TestError::Fail(reason, case) => {
                let (text, done) = render(&bases, &case);
                let path = record_finding(
                    "in-process.toml",
                    &as_file(&done, text.as_deref().unwrap_or("")),
                );
                format!(
                    "a mutated scene failed in process (shrunk; written to {}):\n{reason}",
                    path.display()
                )
            }
            TestError::Abort(reason) => format!("the fuzz was aborted: {reason}"),
        };
        panic!("{message}");
    }
    let built = get("Built");
    let errors = get("ParseError") + get("BuildError");
    assert!(
        built >= (cases as usize) / 20 && errors >= (cases as usize) / 4,
        "the fuzz is vacuous: of {cases} cases {built} built and {errors} were refused"
    );
}

// ---------------------------------------------------------------------------------------------
// In a child process: the command line's solve.

/// Every file (not folder) under `dir`, recursively (none when it does not exist).
fn files_under(dir: &Path) -> Vec<PathBuf> {
    written(dir)
        .into_iter()
        .map(|relative| dir.join(relative))
        .filter(|path| path.is_file())
        .collect()
}

/// A word that is a non-finite number as Rust, C or JSON-ish writers spell it.
fn non_finite_word(token: &str) -> bool {
    let t = token.trim_start_matches(['+', '-']).to_ascii_lowercase();
    matches!(t.as_str(), "nan" | "inf" | "infinity" | "null")
}

/// The non-finite numbers of an XML file (VTU, PVD): in attribute values and, token by token,
/// in every `DataArray` (whose tokens must all be numbers).
fn check_xml(text: &str, problems: &mut Vec<String>) {
    for attribute in text.split('"').skip(1).step_by(2) {
        if non_finite_word(attribute.trim()) {
            problems.push(format!("attribute value {attribute:?}"));
        }
    }
    let mut rest = text;
    while let Some(open) = rest.find("<DataArray") {
        let after = &rest[open..];
        let Some(gt) = after.find('>') else {
            problems.push("unclosed <DataArray".into());
            return;
        };
        let body_and_more = &after[gt + 1..];
        let Some(close) = body_and_more.find("</DataArray>") else {
            problems.push("<DataArray without </DataArray>".into());
            return;
        };
        let header = &after[..gt];
        for (i, token) in body_and_more[..close].split_whitespace().enumerate() {
            match token.parse::<f64>() {
                Ok(x) if x.is_finite() => {}
                _ => {
                    problems.push(format!("{header}>: token {i} is {token:?}"));
                    break;
                }
            }
        }
        rest = &body_and_more[close..];
    }
}

/// Every position and morph-target displacement of a glTF binary must be finite (read with the
/// `gltf` crate); a file it cannot read is a problem.
fn check_glb(file: &std::path::Path, problems: &mut Vec<String>) {
    let gltf = match fs::read(file).map(|b| gltf::Gltf::from_slice(&b)) {
        Ok(Ok(g)) => g,
        Ok(Err(e)) => return problems.push(format!("not a readable glTF: {e}")),
        Err(e) => return problems.push(format!("cannot read: {e}")),
    };
    let blob = gltf.blob.clone().unwrap_or_default();
    for mesh in gltf.meshes() {
        for p in mesh.primitives() {
            let reader = p.reader(|_| Some(&blob[..]));
            let mut all: Vec<[f32; 3]> =
                reader.read_positions().map_or(Vec::new(), |r| r.collect());
            for (t, _, _) in reader.read_morph_targets() {
                all.extend(t.into_iter().flatten());
            }
            if all.iter().flatten().any(|x| !x.is_finite()) {
                problems.push(format!("mesh {:?}: a non-finite position", mesh.name()));
            }
        }
    }
}

/// The coordinates of an OBJ file (`v`, `vn`, `vt` lines) must be finite numbers.
fn check_obj(text: &str, problems: &mut Vec<String>) {
    for (l, line) in text.lines().enumerate() {
        let mut tokens = line.split_whitespace();
        if matches!(tokens.next(), Some("v" | "vn" | "vt")) {
            for token in tokens {
                if !token.parse::<f64>().is_ok_and(f64::is_finite) {
                    problems.push(format!("line {}: {line:?}", l + 1));
                    break;
                }
            }
        }
    }
}

/// Every value of a JSON file: numbers are finite by construction, a null is a non-finite
/// number (serde_json writes NaN and ±inf as null; the report leaves absent fields out).
fn check_json(text: &str, problems: &mut Vec<String>) {
    fn walk(v: &serde_json::Value, path: &mut String, problems: &mut Vec<String>) {
        match v {
            serde_json::Value::Null => problems.push(format!("null at {path}")),
            serde_json::Value::Array(a) => {
                for (i, x) in a.iter().enumerate() {
                    let len = path.len();
                    path.push_str(&format!("[{i}]"));
                    walk(x, path, problems);
                    path.truncate(len);
                }
            }
            serde_json::Value::Object(o) => {
                for (k, x) in o {
                    let len = path.len();
                    path.push('.');
                    path.push_str(k);
                    walk(x, path, problems);
                    path.truncate(len);
                }
            }
            _ => {}
        }
    }
    match serde_json::from_str::<serde_json::Value>(text) {
        Ok(v) => walk(&v, &mut String::new(), problems),
        Err(e) => problems.push(format!("not JSON: {e}")),
    }
}

/// Checks the files a successful solve wrote.
fn check_output(out: &Path) -> Vec<String> {
    let mut problems = Vec::new();
    let files = files_under(out);
    if files.is_empty() {
        problems.push("output: exit code 0 but nothing written to --out".into());
    }
    for file in files {
        let name = file
            .strip_prefix(out)
            .unwrap_or(&file)
            .display()
            .to_string();
        let text = match fs::read(&file) {
            // A binary VTU as its ASCII equivalent (a file that does not decode is a problem).
            Ok(bytes) if file.extension().is_some_and(|e| e == "vtu") => {
                match common::vtu::to_ascii(&bytes) {
                    Ok(text) => text,
                    Err(e) => {
                        problems.push(format!("output: {name}: not a readable VTU: {e}"));
                        continue;
                    }
                }
            }
            Ok(bytes) => String::from_utf8_lossy(&bytes).to_string(),
            Err(e) => {
                problems.push(format!("output: {name}: cannot read: {e}"));
                continue;
            }
        };
        let mut found = Vec::new();
        match file.extension().and_then(|e| e.to_str()) {
            Some("vtu" | "pvd") => check_xml(&text, &mut found),
            Some("obj") => check_obj(&text, &mut found),
            Some("glb") => check_glb(&file, &mut found),
            Some("json") => check_json(&text, &mut found),
            _ => {
                for token in
                    text.split(|c: char| c.is_whitespace() || ",;:\"'=<>[]{}()".contains(c))
                {
                    if non_finite_word(token) {
                        found.push(format!("word {token:?}"));
                        break;
                    }
                }
            }
        }
        let n = found.len();
        found.truncate(5);
        for f in found {
            problems.push(format!("non-finite output: {name}: {f}"));
        }
        if n > 5 {
            problems.push(format!("non-finite output: {name}: … {} more", n - 5));
        }
    }
    problems
}

/// What a solve did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Verdict {
    /// Exit code 0, output checked.
    Solved,
    /// Exit code 2: a keyframe the solver could not follow to its pose; the frames up to where
    /// it stopped are written (output checked).
    Stopped,
    /// Exit code 1.
    Refused,
    /// Killed at the time limit.
    TimedOut,
    /// Anything else (a signal, another code).
    Other,
}

struct SolveOutcome {
    solved: Verdict,
    seconds: f64,
    /// The problems found, each "category: detail" (empty when the case passes).
    problems: Vec<String>,
    stderr: String,
}

impl SolveOutcome {
    fn categories(&self) -> BTreeSet<String> {
        self.problems
            .iter()
            .map(|p| p.split(':').next().unwrap_or(p).to_string())
            .collect()
    }
}

/// Solves one scene text in `dir` (wiped first) and checks the run.
fn check_solve(text: &str, dir: &Path) -> SolveOutcome {
    let _ = fs::remove_dir_all(dir);
    fs::create_dir_all(dir).expect("case folder");
    let scene = dir.join(FILE);
    fs::write(&scene, text).expect("write scene");
    let out = dir.join("out");
    let stderr_file = dir.join("stderr.txt");
    let mut problems = Vec::new();
    let (ending, elapsed) =
        match solve_limited(&scene, &out, &stderr_file, TIME_LIMIT, ADDRESS_SPACE_LIMIT) {
            Ok(r) => r,
            Err(e) => panic!("cannot run prehensile: {e}"),
        };
    let stderr = String::from_utf8_lossy(&fs::read(&stderr_file).unwrap_or_default()).to_string();
    let solved = match &ending {
        Ending::TimedOut => Verdict::TimedOut,
        Ending::Exited(s) => match (s.code(), signal(s)) {
            (Some(0), _) => Verdict::Solved,
            (Some(1), _) => Verdict::Refused,
            (Some(2), _) => Verdict::Stopped,
            (Some(101), _) => {
                problems.push("panic: exit code 101".to_string());
                Verdict::Other
            }
            (Some(c), _) => {
                problems.push(format!("exit code: {c}, not 0, 1 or 2"));
                Verdict::Other
            }
            (None, Some(sig)) => {
                problems.push(format!("signal: killed by signal {sig}"));
                Verdict::Other
            }
            (None, None) => {
                problems.push(format!("ending: {s}"));
                Verdict::Other
            }
        },
    };
    if stderr.contains("panicked at") {
        problems.push("panic: stderr says \"panicked at\"".into());
    }
    match solved {
        Verdict::Solved | Verdict::Stopped => problems.extend(check_output(&out)),
        Verdict::Refused => {
            let files = written(&out);
            if !files.is_empty() {
                problems.push(format!("written on error: {}", files.join(", ")));
            }
        }
        _ => {}
    }
    SolveOutcome {
        solved,
        seconds: elapsed.as_secs_f64(),
        problems,
        stderr,
    }
}

/// A generated subprocess case: its value tree (to shrink it) is kept on the main thread.
struct Generated {
    text: Option<String>,
    done: Vec<String>,
}

#[test]
fn mutated_scenes_solve_or_fail_cleanly() {
    let _turn = ONE_AT_A_TIME.lock().unwrap_or_else(|p| p.into_inner());
    let start = Instant::now();
    let bases: Vec<Base> = shipped_scenes()
        .into_iter()
        .map(|b| shrunk(b, false))
        .collect();
    let n: usize = env_number("FUZZ_SOLVE_CASES", SOLVE_CASES);
    let seed: u64 = env_number("FUZZ_SEED", SEED).wrapping_add(1);
    let work = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fuzz_scenes/solve");
    let _ = fs::remove_dir_all(&work);
    fs::create_dir_all(&work).expect("work folder");

    let strategy = case_strategy(bases.len(), 1, 1);
    let mut runner = runner(n as u32, seed);
    let mut trees = Vec::with_capacity(n);
    let mut generated = Vec::with_capacity(n);
    for _ in 0..n {
        let tree = strategy.new_tree(&mut runner).expect("a case");
        let (text, done) = render(&bases, &tree.current());
        trees.push(tree);
        generated.push(Generated { text, done });
    }

    // Run them, WORKERS at a time.
    let next = AtomicUsize::new(0);
    let outcomes: Mutex<Vec<Option<SolveOutcome>>> = Mutex::new((0..n).map(|_| None).collect());
    std::thread::scope(|s| {
        for _ in 0..WORKERS {
            s.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::Relaxed);
                let Some(case) = generated.get(i) else { break };
                let Some(text) = &case.text else { continue };
                let dir = work.join(format!("case_{i:03}"));
                let outcome = check_solve(text, &dir);
                if outcome.problems.is_empty() {
                    let _ = fs::remove_dir_all(dir.join("out"));
                }
                outcomes.lock().unwrap()[i] = Some(outcome);
            });
        }
    });
    let outcomes = outcomes.into_inner().unwrap();

    let mut summary = std::collections::BTreeMap::<&str, usize>::new();
    let mut lines = Vec::new();
    for (i, (case, outcome)) in generated.iter().zip(&outcomes).enumerate() {
        let (what, seconds) = match outcome {
            None => ("not writable as TOML", 0.0),
            Some(o) if !o.problems.is_empty() => ("FAILED", o.seconds),
            Some(o) => (
                match o.solved {
                    Verdict::Solved => "solved",
                    Verdict::Stopped => "stopped",
                    Verdict::Refused => "refused",
                    Verdict::TimedOut => "timed out",
                    Verdict::Other => "other",
                },
                o.seconds,
            ),
        };
        *summary.entry(what).or_default() += 1;
        let first_error = outcome
            .as_ref()
            .and_then(|o| o.stderr.lines().find(|l| l.starts_with("error")))
            .map(|l| trimmed(l, 100))
            .unwrap_or_default();
        lines.push(format!(
            "  case {i:03} {what:>9} {seconds:5.2} s  {} {first_error}",
            case.done.join("; ")
        ));
    }
    let get = |k: &str| summary.get(k).copied().unwrap_or(0);
    let total = format!(
        "fuzz (solve, seed {seed:#x}, {n} cases, {:.1} s, {WORKERS} at a time, limit {} s): {} \
         solved, {} stopped short by the solver (exit 2), {} refused (exit 1), {} timed out, {} not \
         writable as TOML, {} failed",
        start.elapsed().as_secs_f64(),
        TIME_LIMIT.as_secs(),
        get("solved"),
        get("stopped"),
        get("refused"),
        get("timed out"),
        get("not writable as TOML"),
        get("FAILED"),
    );
    write_summary("solve", &format!("{}\n{total}", lines.join("\n")));

    // Shrink the failures: fewer, simpler mutations that fail the same way.
    let shrink_start = Instant::now();
    let mut reports = Vec::new();
    for (i, outcome) in outcomes.iter().enumerate() {
        let Some(outcome) = outcome else { continue };
        if outcome.problems.is_empty() {
            continue;
        }
        let categories = outcome.categories();
        let tree = &mut trees[i];
        let mut best = (
            generated[i].text.clone().unwrap_or_default(),
            generated[i].done.clone(),
            outcome.problems.clone(),
            outcome.stderr.clone(),
        );
        let dir = work.join(format!("case_{i:03}_shrinking"));
        let mut steps = 0;
        if tree.simplify() {
            while shrink_start.elapsed() < SHRINK_BUDGET && steps < 60 {
                steps += 1;
                let (text, done) = render(&bases, &tree.current());
                let still_fails = text.as_ref().is_some_and(|text| {
                    let o = check_solve(text, &dir);
                    let fails = !o.categories().is_disjoint(&categories);
                    if fails {
                        best = (
                            text.clone(),
                            done.clone(),
                            o.problems.clone(),
                            o.stderr.clone(),
                        );
                    }
                    fails
                });
                let more = if still_fails {
                    tree.simplify()
                } else {
                    tree.complicate()
                };
                if !more {
                    break;
                }
            }
        }
        let (text, done, problems, stderr) = best;
        let path = record_finding(&format!("solve-case-{i:03}.toml"), &as_file(&done, &text));
        reports.push(format!(
            "\n- case {i:03} (shrunk in {steps} runs; {}):\n    {}\n    stderr: {}",
            path.display(),
            problems.join("\n    "),
            trimmed(&stderr, 800)
        ));
    }
    assert!(
        reports.is_empty(),
        "{} of {n} mutated scenes did not solve or fail cleanly:{}",
        reports.len(),
        reports.concat()
    );
    assert!(
        get("solved") >= 3 && get("refused") >= 3,
        "the fuzz is vacuous: of {n} cases {} solved and {} were refused",
        get("solved"),
        get("refused")
    );
}

// ---------------------------------------------------------------------------------------------
// Scenes the fuzz found failing, minimised: each must solve or fail cleanly too (regressions).

/// (what goes wrong, the scene).
const FOUND: &[(&str, &str)] = &[
    (
        "panic (exit 101) at src/fem/solve.rs:337, index out of bounds: the index of faer's \
         NonPositivePivot equals the number of free equations and indexes the permutation (fixed in \
         d7f4d90: refused)",
        r#"
# A hollow ball, auxetic (poisson -0.99), under 10^4 g, its top node pushed sideways, on the
# nonlinear tier (found as a random scene).
[world]
gravity = [0.0, 0.0, -100000.0]

[solver]
tier = "nonlinear"

[[material]]
name = "m0"
young = 1.0e6
poisson = -0.99
density = 1000.0

[[body]]
name = "b0"
material = "m0"
shape = { shell = { center = [0.0, 0.0, 0.0], inner_radius = 0.4, outer_radius = 0.5, cells = 4, layers = 1 } }

[[constraint]]
name = "held"
body = "b0"
where = { box = { min = [-2.0, -2.0, -2.0], max = [2.0, 2.0, -0.25] } }
displacement = [0.0, 0.0, 0.0]

[[constraint]]
name = "push"
body = "b0"
where = { point = [0.0, 0.0, 1.0] }
displacement = [0.01, 0.0, 0.0]
"#,
    ),
    (
        "the same panic on a solid ball (found as a random scene, shrunk by the fuzz; fixed in \
         d7f4d90)",
        r#"
[world]
gravity = [0.0, 0.0, -9.81]

[solver]
tier = "nonlinear"
volumetric = "full"

[[material]]
name = "m0"
young = 1000000.0
poisson = -0.99
density = 100000.0

[[body]]
name = "b0"
material = "m0"
shape = { sphere = { center = [0.0, 0.0, 0.0], radius = 500.0, cells = 3 } }

[[constraint]]
name = "b0 held"
body = "b0"
where = { box = { min = [-2000.0, -2000.0, -2000.0], max = [2000.0, 2000.0, -250.0] } }
displacement = [0.0, 0.0, 0.0]

[[constraint]]
name = "c0"
body = "b0"
where = { box = { min = [-2000.0, -2000.0, 250.0], max = [2000.0, 2000.0, 2000.0] } }
displacement = [0.0, 0.0, 0.0]

[[load]]
name = "l0"
body = "b0"
where = { box = { min = [-2000.0, -2000.0, -2000.0], max = [2000.0, 2000.0, -250.0] } }
force = [0.0, 0.0, -10.0]

[[load]]
name = "l1"
body = "b0"
where = { surface = "outer" }
pressure = 10000.0
"#,
    ),
    (
        "(fixed in 1f1ed8c: refused) abort (SIGABRT) under the 4 GiB address-space limit, \"memory allocation of 1465027200 \
         bytes failed\" in fem::hyperelastic_body::internal_forces (solve_static_nonlinear): the \
         nonlinear statics allocates past the memory budget; with the linear tier the same scene \
         fails cleanly (\"sparse Cholesky failed: OutOfMemory\"), without `refine` it solves",
        r#"
# A refined hollow ball of 130 cells per face edge on the nonlinear tier (found as a random scene
# whose `cells` were blown up).
[solver]
tier = "nonlinear"

[[material]]
name = "m0"
young = 1.0e6
poisson = 0.3
density = 1000.0

[[body]]
name = "b0"
material = "m0"
shape = { shell = { center = [0.0, 0.0, 0.0], inner_radius = 0.4, outer_radius = 0.5, cells = 130, layers = 1, refine = { toward = [0.0, 0.0, 1.0], size = 0.03125 } } }

[[constraint]]
name = "held"
body = "b0"
where = { box = { min = [-2.0, -2.0, -2.0], max = [2.0, 2.0, -0.25] } }
displacement = [0.0, 0.0, 0.0]
"#,
    ),
];

/// The scenes of [`FOUND`], each solved as a subprocess case.
#[test]
fn found_scenes_solve_or_fail_cleanly() {
    let _turn = ONE_AT_A_TIME.lock().unwrap_or_else(|p| p.into_inner());
    let work = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fuzz_scenes/found");
    let _ = fs::remove_dir_all(&work);
    let mut failures = Vec::new();
    for (i, (what, text)) in FOUND.iter().enumerate() {
        let outcome = check_solve(text, &work.join(format!("found_{i}")));
        println!(
            "found scene {i}: {:?} in {:.2} s, {} problems",
            outcome.solved,
            outcome.seconds,
            outcome.problems.len()
        );
        if !outcome.problems.is_empty() {
            failures.push(format!(
                "\n- found scene {i} ({what}):\n    {}\n    stderr: {}",
                outcome.problems.join("\n    "),
                trimmed(&outcome.stderr, 400)
            ));
        }
    }
    assert!(
        failures.is_empty(),
        "{} of the {} scenes the fuzz found still do not solve or fail cleanly:{}",
        failures.len(),
        FOUND.len(),
        failures.concat()
    );
}

/// The output checks see what they look for (so that a clean fuzz run means something): a
/// NaN in a VTU data array, an infinity in a PVD attribute and in OBJ coordinates, a null in the
/// report, and nothing in clean files.
#[test]
fn output_checks_catch_non_finite_numbers() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fuzz_scenes/checks");
    let _ = fs::remove_dir_all(&dir);
    let write = |name: &str, text: &str| {
        fs::create_dir_all(dir.join(name).parent().unwrap()).unwrap();
        fs::write(dir.join(name), text).unwrap();
    };
    let vtu = |x: &str| {
        format!(
            "<VTKFile>\n<DataArray type=\"Float64\" Name=\"displacement\" format=\"ascii\">\n0 \
             1.5e-3 -2\n{x} 0 0\n</DataArray>\n<DataArray type=\"Int32\" Name=\"bone_id\" \
             format=\"ascii\">\n-1 3\n</DataArray>\n</VTKFile>\n"
        )
    };
    write("clean/frame_0000.vtu", &vtu("4"));
    write(
        "clean/frames.pvd",
        "<Collection>\n<DataSet timestep=\"0.5\" file=\"frame_0000.vtu\"/>\n</Collection>\n",
    );
    write(
        "clean/hand_0000.obj",
        "o skin\nv 0 1 2.5e-3\nvn 0 0 1\nf 1 2 3\n",
    );
    write(
        "clean/report.json",
        r#"{"frames": [{"time": 0.0, "max": 1e300, "warnings": ["inf NaN"]}]}"#,
    );
    assert_eq!(check_output(&dir.join("clean")), Vec::<String>::new());

    write("dirty/frame_0000.vtu", &vtu("NaN"));
    write(
        "dirty/frames.pvd",
        "<Collection>\n<DataSet timestep=\"inf\" file=\"frame_0000.vtu\"/>\n</Collection>\n",
    );
    write("dirty/hand_0000.obj", "o skin\nv 0 -inf 2\nf 1 2 3\n");
    write(
        "dirty/report.json",
        r#"{"frames": [{"time": 0.0, "max": null}]}"#,
    );
    let problems = check_output(&dir.join("dirty"));
    for (file, what) in [
        ("frame_0000.vtu", "\"NaN\""),
        ("frames.pvd", "\"inf\""),
        ("hand_0000.obj", "-inf"),
        ("report.json", "null at .frames[0].max"),
    ] {
        assert!(
            problems
                .iter()
                .any(|p| p.contains(file) && p.contains(what)),
            "{file}: {what} not found in {problems:#?}"
        );
    }
    assert!(!check_output(&dir.join("nothing")).is_empty());
}
