//! `supergrain contact`: one pair from flags, or many as JSON Lines.

use std::io::{BufRead, Write};
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, Result, bail};
use clap::Parser;
use supergrain::contact::{Contact, contact, contact_quadtree, overlap_regions, unresolved};
use supergrain::io::{ContactAnswer, ContactQuery, ShapeJson};
use supergrain::render::{answer_svg, contact_svg};
use supergrain::subdivision::{MAX_DEPTH, Precision};

use crate::output::{Plans, Target};

#[derive(Parser)]
#[command(after_help = "\
SHAPE is either `X,Y,ANGLE,SX,SY,EX,EY` (centre, angle in radians, semi-axes, exponents) or the
JSON object {\"center\": [x, y], \"angle\": a, \"semi_axes\": [sx, sy], \"exponents\": [ex, ey]}.

Output, one JSON line per pair:
  {\"overlap\": bool, \"a_deepest\": [x, y] | null, \"b_deepest\": ..., \"a_push\": [dx, dy] | null,
   \"b_push\": ..., \"cells\": n, \"contacts\": [{\"a_deepest\", \"b_deepest\", \"a_push\", \"b_push\"}, ...]}
a_deepest is the point of A most interior to B; a_push moves it along grad f_B to B's boundary.
`overlap` is certified: true only if a point was proven inside both shapes by interval
arithmetic. false means apart, or touching within the tolerance: no point of one shape lies
more than the tolerance inside the other. The tolerance is a distance: half a final cell when
the certified path answered (cells: 0), four final cells from the quadtree (a final cell: the
longest side of the pair's box intersection over 2^depth; above depth 7, a spike thinner than a
cell is searched at depth 7's resolution, so four cells of depth 7 there). The pushes point apart along one
normal. `contacts` lists every overlap region (two stars, or a star on a face, can touch in
several places), the one of the fields above first, the others deepest first; regions nearer
each other than a final cell (at most depth 10) count as one.
Exponents must lie in [0.25, 1000] and semi-axes in [1e-9, 1e9]. A pair whose final cell is finer
than double precision resolves at its coordinates (a grain a million times smaller than the
other, or far from the origin; about 16 ulps of |centres| + radii) is refused with an error,
as its tolerance could not be held.
The certified path answers every pair: Newton's method with a proof for convex pairs (every
exponent >= 1), and a branch and bound over one shape's closed-form boundary for stars and
when Newton finds no proof; either proves the deepest points inside both shapes and deepest
up to half a final cell, or the shapes apart, and `cells` is then 0. When neither proves
anything, the quadtree answers and `cells` counts the cells it classified. --quadtree always
uses the quadtree (the paper's).

Examples:
  supergrain contact --a 0,0,0,1,1,2,2 --b 1.9,0,0.3,1,0.5,4,4
  supergrain contact --a -1,0,0,1,1,2,2 --b 0.9,0,0,1,1,2,2
  echo '{\"a\": {\"center\": [0,0], \"semi_axes\": [1,1], \"exponents\": [2,2]}, \"b\": {\"center\": [1.5,0], \"semi_axes\": [1,1], \"exponents\": [2,2]}}' | supergrain contact --batch -")]
pub struct Args {
    /// Shape A (see SHAPE below).
    #[arg(long, value_name = "SHAPE", required_unless_present = "batch", conflicts_with = "batch", allow_hyphen_values = true, value_parser = parse_shape)]
    a: Option<ShapeJson>,
    /// Shape B (see SHAPE below).
    #[arg(long, value_name = "SHAPE", required_unless_present = "batch", conflicts_with = "batch", allow_hyphen_values = true, value_parser = parse_shape)]
    b: Option<ShapeJson>,
    /// Read pairs as JSON Lines from FILE (or - for standard input): {"a": SHAPE, "b": SHAPE},
    /// optionally with "depth" and "eps"; each SHAPE an object or the string
    /// "X,Y,ANGLE,SX,SY,EX,EY". Each output line answers the input line of the same
    /// number; a bad line is answered {"error": "..."} and the exit code is 1.
    #[arg(long, value_name = "FILE")]
    batch: Option<PathBuf>,
    /// Maximum quadtree depth (the paper uses 7).
    #[arg(long, default_value_t = 7, value_parser = clap::value_parser!(u32).range(0..=i64::from(MAX_DEPTH)))]
    depth: u32,
    /// Tolerance: cell sides shorter than this are not split (0: depth alone decides).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    eps: f64,
    /// Answer by the paper's quadtree alone, never by the certified path.
    #[arg(long)]
    quadtree: bool,
    /// Write the answers to FILE instead of standard output (replaced only when complete).
    #[arg(short, long, value_name = "FILE")]
    output: Option<PathBuf>,
    /// Also draw the collision test (quadtree cells by class, deepest points, penetration
    /// vectors) as an SVG picture. Single pair only.
    #[arg(long, value_name = "FILE", conflicts_with = "batch")]
    svg: Option<PathBuf>,
}

fn parse_shape(s: &str) -> Result<ShapeJson, String> {
    let shape: ShapeJson = s.parse()?;
    shape.to_shape().map_err(|e| e.to_string())?;
    Ok(shape)
}

pub fn run(args: Args) -> Result<ExitCode> {
    let defaults = Precision::new(args.depth, args.eps).context("invalid --depth/--eps")?;
    // Plan every output before any work, so a bad path, or -o and --svg on one path, fails
    // fast.
    let mut plans = Plans::default();
    let out_to = plans.file("--output", args.output.as_deref())?;
    let svg_to = plans.file("--svg", args.svg.as_deref())?;
    let mut out = match out_to {
        Some(to) => to,
        None => Target::resolve(None)?,
    }
    .open()?;
    let mut svg = svg_to.as_ref().map(Target::open).transpose()?;
    let mut failed = 0usize;
    if let Some(path) = &args.batch {
        let input: Box<dyn BufRead> = if path.as_os_str() == "-" {
            Box::new(std::io::stdin().lock())
        } else {
            let f = std::fs::File::open(path)
                .with_context(|| format!("cannot read batch file {}", path.display()))?;
            Box::new(std::io::BufReader::new(f))
        };
        // Lines are read as bytes, so that one not in UTF-8 is answered with an error like any
        // other bad line, and the lines after it still are.
        for (i, line) in input.split(b'\n').enumerate() {
            let line = line.with_context(|| format!("cannot read line {} of the batch", i + 1))?;
            let line = line.strip_suffix(b"\r").unwrap_or(&line);
            let answered = match std::str::from_utf8(line) {
                Ok(line) => answer_line(line, &defaults, args.quadtree),
                Err(e) => Err(format!(
                    "not UTF-8 text (byte {} is 0x{:02X})",
                    e.valid_up_to() + 1,
                    line[e.valid_up_to()]
                )),
            };
            match answered {
                Ok((answer, _)) => serde_json::to_writer(&mut out, &answer)?,
                Err(msg) => {
                    failed += 1;
                    eprintln!("error: line {}: {msg}", i + 1);
                    serde_json::to_writer(
                        &mut out,
                        &serde_json::json!({ "error": format!("line {}: {msg}", i + 1) }),
                    )?;
                }
            }
            out.write_all(b"\n")?;
        }
    } else {
        let (Some(a), Some(b)) = (args.a, args.b) else {
            bail!("give both --a and --b, or --batch");
        };
        let query = ContactQuery {
            a,
            b,
            depth: None,
            eps: None,
        };
        let (answer, found) =
            answer(&query, &defaults, args.quadtree).map_err(anyhow::Error::msg)?;
        if let Some(svg_out) = svg.as_mut() {
            let ((a, pa), (b, pb), precision) = query.resolve(&defaults)?;
            // The picture shows what answered: the quadtree's cells when it did, else the
            // certified path's points alone (it classifies no cell).
            let picture = if args.quadtree || found.cells > 0 {
                contact_svg(&a, &pa, &b, &pb, &precision, 640).0
            } else {
                answer_svg(&a, &pa, &b, &pb, &found, 640)
            };
            svg_out.write_all(picture.as_bytes())?;
        }
        serde_json::to_writer(&mut out, &answer)?;
        out.write_all(b"\n")?;
    }
    out.finish()?;
    if let Some(svg_out) = svg {
        svg_out.finish()?;
    }
    if failed > 0 {
        eprintln!("{failed} line(s) could not be answered");
        return Ok(ExitCode::FAILURE);
    }
    Ok(ExitCode::SUCCESS)
}

fn answer_line(
    line: &str,
    defaults: &Precision,
    quadtree: bool,
) -> Result<(ContactAnswer, Contact), String> {
    if line.trim().is_empty() {
        return Err("empty line, expected {\"a\": SHAPE, \"b\": SHAPE}".into());
    }
    let query: ContactQuery =
        serde_json::from_str(line).map_err(|e| format!("not a contact query: {e}"))?;
    answer(&query, defaults, quadtree)
}

fn answer(
    query: &ContactQuery,
    defaults: &Precision,
    quadtree: bool,
) -> Result<(ContactAnswer, Contact), String> {
    let ((a, pa), (b, pb), precision) = query.resolve(defaults).map_err(|e| e.to_string())?;
    if let Some((cell, resolution)) = unresolved(&a, &pa, &b, &pb, &precision) {
        // (Rounded up in the message, so that the value shown is enough.)
        let enough = resolution * 1.1;
        if !enough.is_finite() {
            return Err(
                "the pair lies beyond what double precision resolves (its coordinates and \
                 sizes add up to more than the largest number): place the grains nearer the \
                 origin"
                    .into(),
            );
        }
        return Err(format!(
            "the pair's final cell ({cell:.2e}) is finer than double precision resolves at \
             its coordinates and sizes (about {resolution:.2e}), so its answer could not be \
             held to the tolerance: set --eps (or \"eps\") to at least {enough:.1e}, lower \
             --depth, or place the grains nearer the origin"
        ));
    }
    let method = if quadtree { contact_quadtree } else { contact };
    let found = method(&a, &pa, &b, &pb, &precision);
    let regions = overlap_regions(&a, &pa, &b, &pb, &precision, found.penetration.as_ref());
    Ok((ContactAnswer::from(&found).with_regions(&regions), found))
}
