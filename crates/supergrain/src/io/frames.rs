//! Per-frame outputs: trajectory rows (CSV) and VTK point files for ParaView.

use std::io::{self, Write};

use crate::settings::Model;
use crate::world::World;

/// The trajectory CSV header: one row per grain and frame.
pub const TRAJECTORY_HEADER: &str = "step,time,id,x,y,angle,vx,vy,sx,sy,ex,ey,group";

/// The columns the soft model's trajectory adds after [`TRAJECTORY_HEADER`]'s: the grain's
/// material, its mass and its moment of inertia about its centre. The paper's model has no
/// materials (unit masses, projection): its trajectory stays as it was.
pub const MATERIAL_COLUMNS: &str = "density,friction,restitution,rolling_resistance,mass,inertia";

/// The header of `world`'s trajectory: [`TRAJECTORY_HEADER`], then for the soft model
/// [`MATERIAL_COLUMNS`].
pub fn trajectory_header(world: &World) -> String {
    match world.settings.model {
        Model::Paper => TRAJECTORY_HEADER.to_string(),
        Model::Soft => format!("{TRAJECTORY_HEADER},{MATERIAL_COLUMNS}"),
    }
}

/// Appends one frame of the trajectory: a row per grain, `id` its [`crate::body::BodyId`] (its
/// order of appearance, never reused when grains leave; the columns of [`trajectory_header`]).
pub fn write_trajectory_frame(world: &World, out: &mut impl Write) -> io::Result<()> {
    let time = world.time();
    let soft = world.settings.model == Model::Soft;
    for (i, b) in world.bodies.iter().enumerate() {
        let v = world.velocity(i);
        let s = b.shape.semi_axes();
        let [ex, ey] = b.shape.exponents();
        write!(
            out,
            "{},{},{},{},{},{},{},{},{},{},{},{},{}",
            world.step,
            time,
            b.id,
            b.center.x,
            b.center.y,
            b.angle,
            v.x,
            v.y,
            s.x,
            s.y,
            ex,
            ey,
            b.group
        )?;
        if soft {
            let m = world.material(i);
            let (mass, inertia) = m.mass_and_inertia(&b.shape);
            write!(
                out,
                ",{},{},{},{},{mass},{inertia}",
                m.density, m.friction, m.restitution, m.rolling_resistance
            )?;
        }
        writeln!(out)?;
    }
    Ok(())
}

/// One frame as a legacy-format VTK point file: grain centres as points, with the grain's id
/// (its [`crate::body::BodyId`], the trajectory's `id`, so a grain can be followed from frame
/// to frame), the semi-axes, the local x axis, exponents, superquadric roundness (2 / exponent),
/// angle, velocity and scene group as point data, so that ParaView can glyph them (see docs/reference.md); for the soft
/// model also the material, mass and moment of inertia ([`MATERIAL_COLUMNS`]'s names).
pub fn write_vtk_frame(world: &World, out: &mut impl Write) -> io::Result<()> {
    let n = world.bodies.len();
    writeln!(out, "# vtk DataFile Version 3.0")?;
    writeln!(out, "supergrain step {}", world.step)?;
    writeln!(out, "ASCII")?;
    writeln!(out, "DATASET POLYDATA")?;
    writeln!(out, "POINTS {n} double")?;
    for b in &world.bodies {
        writeln!(out, "{} {} 0", b.center.x, b.center.y)?;
    }
    writeln!(out, "VERTICES {n} {}", 2 * n)?;
    for i in 0..n {
        writeln!(out, "1 {i}")?;
    }
    writeln!(out, "POINT_DATA {n}")?;
    writeln!(out, "SCALARS id int 1")?;
    writeln!(out, "LOOKUP_TABLE default")?;
    for b in &world.bodies {
        writeln!(out, "{}", b.id)?;
    }
    // Three components: ParaView's glyph scale wants 3-vectors; z is a nominal thickness.
    writeln!(out, "VECTORS semi_axes double")?;
    for b in &world.bodies {
        let s = b.shape.semi_axes();
        writeln!(out, "{} {} {}", s.x, s.y, s.x.min(s.y))?;
    }
    // The grain's local x axis, for ParaView's Glyph orientation.
    writeln!(out, "VECTORS axis double")?;
    for b in &world.bodies {
        writeln!(out, "{} {} 0", b.angle.cos(), b.angle.sin())?;
    }
    writeln!(out, "VECTORS velocity double")?;
    for i in 0..n {
        let v = world.velocity(i);
        writeln!(out, "{} {} 0", v.x, v.y)?;
    }
    for (name, f) in [
        ("exponent_x", (|e: [f64; 2]| e[0]) as fn([f64; 2]) -> f64),
        ("exponent_y", |e| e[1]),
        ("roundness_x", |e| 2.0 / e[0]),
        ("roundness_y", |e| 2.0 / e[1]),
    ] {
        writeln!(out, "SCALARS {name} double 1")?;
        writeln!(out, "LOOKUP_TABLE default")?;
        for b in &world.bodies {
            writeln!(out, "{}", f(b.shape.exponents()))?;
        }
    }
    writeln!(out, "SCALARS angle double 1")?;
    writeln!(out, "LOOKUP_TABLE default")?;
    for b in &world.bodies {
        writeln!(out, "{}", b.angle)?;
    }
    writeln!(out, "SCALARS angle_degrees double 1")?;
    writeln!(out, "LOOKUP_TABLE default")?;
    for b in &world.bodies {
        writeln!(out, "{}", b.angle.to_degrees())?;
    }
    writeln!(out, "SCALARS group int 1")?;
    writeln!(out, "LOOKUP_TABLE default")?;
    for b in &world.bodies {
        writeln!(out, "{}", b.group)?;
    }
    if world.settings.model == Model::Soft {
        let grains: Vec<_> = (0..n)
            .map(|i| {
                let m = world.material(i);
                let (mass, inertia) = m.mass_and_inertia(&world.bodies[i].shape);
                [
                    m.density,
                    m.friction,
                    m.restitution,
                    m.rolling_resistance,
                    mass,
                    inertia,
                ]
            })
            .collect();
        for (k, name) in MATERIAL_COLUMNS.split(',').enumerate() {
            writeln!(out, "SCALARS {name} double 1")?;
            writeln!(out, "LOOKUP_TABLE default")?;
            for g in &grains {
                writeln!(out, "{}", g[k])?;
            }
        }
    }
    Ok(())
}

/// The header of `run --forces`: one row per contact of the soft model.
pub const FORCES_HEADER: &str = "step,time,a,b,wall,x,y,nx,ny,normal_force,tangent_force";

/// One frame of `run --forces`: each contact's grains by id (`b` empty and `wall` set for a wall:
/// 0 left, 1 right, 2 floor, then the planes), point, normal from A to B, and the normal and
/// tangential force on B.
pub fn write_forces_frame(world: &World, out: &mut impl Write) -> io::Result<()> {
    let time = world.time();
    let id = |i: usize| world.bodies[i].id.to_string();
    for f in &world.soft.forces {
        let (a, b, wall) = match f.wall {
            Some(w) => (id(f.b), String::new(), w.to_string()),
            None => (id(f.a), id(f.b), String::new()),
        };
        writeln!(
            out,
            "{},{},{},{},{},{},{},{},{},{},{}",
            world.step,
            time,
            a,
            b,
            wall,
            f.point.x,
            f.point.y,
            f.normal.x,
            f.normal.y,
            // (`+ 0.0`: a force of -0, from a negated 0, is written 0.)
            f.normal_force + 0.0,
            f.tangent_force + 0.0
        )?;
    }
    Ok(())
}
