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
