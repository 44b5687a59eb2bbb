use crate::geometry::Vec2;

/// Disk-disk contact from the centre distance (paper IV-A, the paper's circles-only comparison):
/// the unit normal from A to B and the depth of the overlap, or `None` when apart.
#[inline]
pub fn disk_disk(ca: Vec2, ra: f64, cb: Vec2, rb: f64) -> Option<(Vec2, f64)> {
    let d = cb - ca;
    let dist2 = d.dot(d);
    let reach = ra + rb;
    if dist2 >= reach * reach {
        return None;
    }
    let dist = dist2.sqrt();
    let normal = if dist > 0.0 {
        d * (1.0 / dist)
    } else {
        Vec2::new(1.0, 0.0)
    };
    Some((normal, reach - dist))
}

/// Two disks by the closed form, with the certificate the narrow phase gives every pair: the
/// overlap is reported only when proven (the squared centre distance below the squared reach by
/// more than its rounding: each is a handful of correctly rounded operations, at most `8u`
/// relative, `u = 2^-53`, so `1e-14` relative covers both with room), and otherwise the disks
/// are apart or touching within that rounding, far inside the narrow phase's tolerance of half
/// a final cell. The deepest points lie on the centre line, and each push along it by the
/// depth separates the disks exactly. The deepest point of A in B is A's point nearest B's
/// centre, or that centre when A holds it (as the certified path answers). For the soft model's
/// circle pairs: the certified Newton path's answer without its solves.
pub fn disk_disk_certified(ca: Vec2, ra: f64, cb: Vec2, rb: f64) -> super::Contact {
    let d = cb - ca;
    let reach = ra + rb;
    let proven = d.dot(d) < reach * reach * (1.0 - 1e-14);
    // The normal and depth of the plain closed form, once the overlap is proven; a depth
    // beyond B's radius puts B's centre in A.
    let penetration = proven
        .then(|| disk_disk(ca, ra, cb, rb))
        .flatten()
        .map(|(n, depth)| super::Penetration {
            a_deepest: if depth > rb { cb } else { ca + n * ra },
            b_deepest: if depth > ra { ca } else { cb - n * rb },
            a_push: n * -depth,
            b_push: n * depth,
        });
    super::Contact {
        penetration,
        cells: 0,
    }
}
