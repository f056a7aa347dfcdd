//! Fibres as shaded cylinders (or capsules) and the box edges, rasterised
//! with tiny-skia. Orthographic: a cylinder's outline is the hull of its two
//! end ellipses; the side is shaded across its width by the Lambert and
//! Phong terms of the true side normal there, the visible end face flat by
//! its own normal.

use super::camera::Camera;
use super::frame::Fibre;
use glam::DVec3;
use tiny_skia::{
    Color, FillRule, GradientStop, LinearGradient, Paint, Path, PathBuilder, Pixmap, PixmapMut,
    Point, RadialGradient, Rect, Shader, SpreadMode, Stroke, Transform,
};

/// The light: direction toward it (camera frame: up-left, in front).
pub(crate) fn light_of(cam: &Camera) -> DVec3 {
    (-0.45 * cam.right + 0.65 * cam.up + 0.6 * cam.toward).normalize()
}

/// Lambert + Phong of a surface normal `n` (both unit), as a colour.
fn shade(base: [u8; 3], n: DVec3, light: DVec3, toward: DVec3) -> Color {
    let diffuse = n.dot(light).max(0.0);
    let half = (light + toward).normalize();
    let spec = 0.3 * n.dot(half).max(0.0).powi(30);
    let k = 0.38 + 0.62 * diffuse;
    let c = base.map(|b| ((b as f64 / 255.0) * k + spec).min(1.0) as f32);
    Color::from_rgba(c[0], c[1], c[2], 1.0).expect("in range")
}

fn colour(rgb: [u8; 3], k: f64) -> Color {
    Color::from_rgba8(
        (rgb[0] as f64 * k) as u8,
        (rgb[1] as f64 * k) as u8,
        (rgb[2] as f64 * k) as u8,
        255,
    )
}

/// An ellipse with semi-axis vectors `u`, `v` around `c`, as 4 cubics.
fn ellipse(pb: &mut PathBuilder, c: (f64, f64), u: (f64, f64), v: (f64, f64)) {
    const K: f64 = 0.552_284_749_8; // 4/3 (√2 − 1): a quarter circle as one cubic
    let at = |a: f64, b: f64| {
        (
            (c.0 + a * u.0 + b * v.0) as f32,
            (c.1 + a * u.1 + b * v.1) as f32,
        )
    };
    let quarter = [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0), (1.0, 0.0)];
    let (x, y) = at(1.0, 0.0);
    pb.move_to(x, y);
    for w in quarter.windows(2) {
        let ((a0, b0), (a1, b1)) = (w[0], w[1]);
        let p1 = at(a0 + K * a1, b0 + K * b1);
        let p2 = at(a1 + K * a0, b1 + K * b0);
        let p3 = at(a1, b1);
        pb.cubic_to(p1.0, p1.1, p2.0, p2.1, p3.0, p3.1);
    }
    pb.close();
}

/// Draw one fibre in `rgb`. A body of zero length (a sphere) is drawn as
/// the capsule of zero length it is, a shaded disc, whatever `capsule`.
pub(crate) fn fibre(pm: &mut PixmapMut<'_>, cam: &Camera, f: &Fibre, rgb: [u8; 3], capsule: bool) {
    let capsule = capsule || f.length == 0.0;
    let h = 0.5 * f.length * f.axis;
    let (x1, y1, _) = cam.project(f.centre - h);
    let (x2, y2, _) = cam.project(f.centre + h);
    let r = 0.5 * f.diameter * cam.scale;
    let (sx, sy) = (x2 - x1, y2 - y1);
    let len = sx.hypot(sy);
    let mut paint = Paint {
        anti_alias: true,
        ..Paint::default()
    };
    // Under a pixel wide: a line (or a dot), flat.
    if r < 0.75 {
        paint.set_color(colour(rgb, 0.9));
        if len < 0.5 {
            let d = (2.0 * r).max(1.0) as f32;
            if let Some(rect) = Rect::from_xywh(x1 as f32 - 0.5 * d, y1 as f32 - 0.5 * d, d, d) {
                pm.fill_rect(rect, &paint, Transform::identity(), None);
            }
            return;
        }
        let mut pb = PathBuilder::new();
        pb.move_to(x1 as f32, y1 as f32);
        pb.line_to(x2 as f32, y2 as f32);
        if let Some(path) = pb.finish() {
            let stroke = Stroke {
                width: (2.0 * r).max(1.0) as f32,
                ..Stroke::default()
            };
            pm.stroke_path(&path, &paint, &stroke, Transform::identity(), None);
        }
        return;
    }
    let (ux, uy) = if len > 1e-9 {
        (sx / len, sy / len)
    } else {
        (1.0, 0.0)
    };
    let (px, py) = (-uy, ux); // screen perpendicular of the axis
    let light = light_of(cam);
    // The world direction of the screen perpendicular (screen y points down),
    // and the side normal that faces the camera.
    let p3 = (px * cam.right - py * cam.up).normalize_or_zero();
    let c = f.axis.dot(cam.toward);
    let facing = (cam.toward - c * f.axis).normalize_or(p3.cross(f.axis));
    const STOPS: usize = 7;
    let stops: Vec<GradientStop> = (0..STOPS)
        .map(|i| {
            let s = -1.0 + 2.0 * i as f64 / (STOPS - 1) as f64;
            let n = s * p3 + (1.0 - s * s).max(0.0).sqrt() * facing;
            GradientStop::new(
                i as f32 / (STOPS - 1) as f32,
                shade(rgb, n, light, cam.toward),
            )
        })
        .collect();
    let mid = (0.5 * (x1 + x2), 0.5 * (y1 + y2));
    let g0 = Point::from_xy((mid.0 - r * px) as f32, (mid.1 - r * py) as f32);
    let g1 = Point::from_xy((mid.0 + r * px) as f32, (mid.1 + r * py) as f32);
    let Some(side) = LinearGradient::new(g0, g1, stops, SpreadMode::Pad, Transform::identity())
    else {
        return;
    };
    let ends = [(x1, y1), (x2, y2)];
    let (across, along) = ((px, py), (c.abs() * ux, c.abs() * uy));
    // A darker hull 0.8 px wider under the fibre: its outline, so touching
    // fibres of one colour stay apart (a fill: strokes cost far more).
    if r >= 2.0 {
        // End ellipses grown by 0.8 px on both semi-axes.
        let k = (r * c.abs() + 0.8) / (r + 0.8);
        let grown = (k * ux, k * uy);
        if let Some(under) = hull(ends, r + 0.8, across, grown, capsule) {
            paint.set_color(colour(rgb, 0.35));
            pm.fill_path(
                &under,
                &paint,
                FillRule::Winding,
                Transform::identity(),
                None,
            );
        }
    }
    let Some(hull) = hull(ends, r, across, along, capsule) else {
        return;
    };
    paint.shader = side;
    pm.fill_path(
        &hull,
        &paint,
        FillRule::Winding,
        Transform::identity(),
        None,
    );
    if capsule {
        for &e in &ends {
            sphere_cap(pm, e, r, rgb, cam, light);
        }
    } else if c.abs() > 1e-3 {
        // The end face whose outward normal faces the camera.
        let (e, n) = if c > 0.0 {
            (ends[1], f.axis)
        } else {
            (ends[0], -f.axis)
        };
        let mut pb = PathBuilder::new();
        ellipse(&mut pb, e, scaled(across, r), scaled(along, r));
        if let Some(cap) = pb.finish() {
            paint.shader = Shader::SolidColor(shade(rgb, n, light, cam.toward));
            pm.fill_path(&cap, &paint, FillRule::Winding, Transform::identity(), None);
        }
    }
}

fn scaled(v: (f64, f64), k: f64) -> (f64, f64) {
    (k * v.0, k * v.1)
}

/// The outline of a fibre of screen radius `r` between `ends`: the quad of
/// the side and the two end ellipses (unit semi-axes `across` and `along`
/// times `r`), or circles for a capsule.
fn hull(
    ends: [(f64, f64); 2],
    r: f64,
    across: (f64, f64),
    along: (f64, f64),
    capsule: bool,
) -> Option<Path> {
    let mut pb = PathBuilder::new();
    let [(x1, y1), (x2, y2)] = ends;
    let corner =
        |x: f64, y: f64, s: f64| ((x + s * r * across.0) as f32, (y + s * r * across.1) as f32);
    let q = [
        corner(x1, y1, 1.0),
        corner(x2, y2, 1.0),
        corner(x2, y2, -1.0),
        corner(x1, y1, -1.0),
    ];
    pb.move_to(q[0].0, q[0].1);
    for p in &q[1..] {
        pb.line_to(p.0, p.1);
    }
    pb.close();
    for &e in &ends {
        if capsule {
            pb.push_circle(e.0 as f32, e.1 as f32, r as f32);
        } else {
            ellipse(&mut pb, e, scaled(across, r), scaled(along, r));
        }
    }
    pb.finish()
}

/// A capsule's hemispherical end: a radial gradient lit from `light`.
fn sphere_cap(
    pm: &mut PixmapMut<'_>,
    e: (f64, f64),
    r: f64,
    rgb: [u8; 3],
    cam: &Camera,
    light: DVec3,
) {
    let hl = (light.dot(cam.right), -light.dot(cam.up));
    let focus = Point::from_xy(
        (e.0 + 0.45 * r * hl.0) as f32,
        (e.1 + 0.45 * r * hl.1) as f32,
    );
    let stops = vec![
        GradientStop::new(0.0, shade(rgb, light, light, cam.toward)),
        GradientStop::new(1.0, colour(rgb, 0.4)),
    ];
    let centre = Point::from_xy(e.0 as f32, e.1 as f32);
    let Some(shader) = RadialGradient::new(
        focus,
        0.0,
        centre,
        r as f32,
        stops,
        SpreadMode::Pad,
        Transform::identity(),
    ) else {
        return;
    };
    let paint = Paint {
        anti_alias: true,
        shader,
        ..Paint::default()
    };
    if let Some(path) = PathBuilder::from_circle(e.0 as f32, e.1 as f32, r as f32) {
        pm.fill_path(
            &path,
            &paint,
            FillRule::Winding,
            Transform::identity(),
            None,
        );
    }
}

/// The 12 edges of the box, those behind its centre (`back`) or in front.
pub(crate) fn box_edges(pm: &mut Pixmap, cam: &Camera, (lo, hi): (DVec3, DVec3), back: bool) {
    let corner = |k: usize| {
        DVec3::new(
            if k & 1 == 0 { lo.x } else { hi.x },
            if k & 2 == 0 { lo.y } else { hi.y },
            if k & 4 == 0 { lo.z } else { hi.z },
        )
    };
    let centre_depth = cam.project(0.5 * (lo + hi)).2;
    let mut pb = PathBuilder::new();
    for a in 0..8 {
        for bit in [1, 2, 4] {
            if a & bit != 0 {
                continue;
            }
            let (p, q) = (corner(a), corner(a | bit));
            let depth = cam.project(0.5 * (p + q)).2;
            if (depth <= centre_depth + 1e-12 * (hi - lo).length()) == back {
                let (x0, y0, _) = cam.project(p);
                let (x1, y1, _) = cam.project(q);
                pb.move_to(x0 as f32, y0 as f32);
                pb.line_to(x1 as f32, y1 as f32);
            }
        }
    }
    let Some(path) = pb.finish() else { return };
    let mut paint = Paint {
        anti_alias: true,
        ..Paint::default()
    };
    paint.set_color(if back {
        Color::from_rgba8(170, 170, 175, 255)
    } else {
        Color::from_rgba8(90, 90, 95, 255)
    });
    let stroke = Stroke {
        width: 1.3,
        ..Stroke::default()
    };
    pm.stroke_path(&path, &paint, &stroke, Transform::identity(), None);
}
