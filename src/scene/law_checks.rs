//! The checks of every contact law a scene's pairs will use: each two materials' that meet and
//! each wall's own against every material of a body, within the accepted ranges, and the
//! boundaries cohesion cannot act on.

use super::fields::{FieldError, index, join};
use super::materials::Named;
use super::ranges::{SpecContext, check_spec};
use crate::contact_law::ContactSpec;
use crate::dynamics::{BodyInit, Boundary};
use crate::geometry::{Shape, Vec2};
use serde_json::{Map, Value};

/// Checks every contact law a pair that can meet will use: each two materials' that meet
/// (`meets`; the scene's at `contact`, a pair given its own at `pairs[k]`, else at the later
/// material's `materials.<name>`), and each wall's own law against every material of a body,
/// for every density of the scene.
pub(super) fn check_contact_ranges(
    contact: &ContactSpec,
    named: &Named,
    meets: &[(u16, u16)],
    walls: &[Boundary],
    bodies: &[BodyInit],
    gravity: Vec2,
) -> Result<(), FieldError> {
    let by_density = |pick: fn(f64, f64) -> bool| {
        let (k, b) = bodies
            .iter()
            .enumerate()
            .reduce(|a, b| if pick(b.1.density, a.1.density) { b } else { a })
            .expect("at least one body");
        (b.density, format!("bodies[{k}].density"))
    };
    let rho = [by_density(|a, b| a < b), by_density(|a, b| a > b)];
    let g = gravity.norm();
    let m = &named.materials;
    // Two bodies of material 0 meet, or one meets a wall of material 0.
    let scene_used = bodies.len() >= 2 && meets.contains(&(0, 0))
        || walls.iter().any(|w| w.material == Some(0)) && bodies.iter().any(|b| b.material == 0);
    for &(a, b) in meets {
        if (a, b) == (0, 0) && !scene_used {
            continue;
        }
        let pair = m.pair(contact, a, b).expect("checked: the pair mixes");
        let at = match m.pairs.iter().position(|p| (p.0, p.1) == (a, b)) {
            Some(k) => index("pairs", k),
            None if b == 0 => "contact".to_string(),
            None => join("materials", &named.names[b as usize - 1]),
        };
        let ctx = SpecContext {
            at: &at,
            rho: rho.clone(),
            g,
        };
        check_spec(&pair.spec, &pair.other, &ctx)?;
    }
    let mut used: Vec<u16> = bodies.iter().map(|b| b.material).collect();
    used.sort_unstable();
    used.dedup();
    for (w, ws) in walls.iter().enumerate() {
        if ws.material.is_some() {
            continue;
        }
        let at = index("walls", w);
        let ctx = SpecContext {
            at: &at,
            rho: rho.clone(),
            g,
        };
        for &b in &used {
            check_spec(&ws.spec, m.spec(contact, b), &ctx)?;
        }
    }
    Ok(())
}

/// Refuses cohesion against a drum or a segment wall for a body that is not a disk (nor a
/// clump, whose members are disks): a disk's overlap with them has a closed form (a drum: the
/// disk's part beyond the circle, `πr² − lens`; a segment: the half-plane's cap over the face,
/// the cap at the same depth at an end), an ellipse's or a polygon's has none that the kernels
/// give for every contact, so the pull `c ℓ` and its energy `−c A` would have no chord to act on
/// (see `contact_law::cohesion`). The error names the key that gives the pair its cohesion: the
/// wall's own `cohesion`, its material's, or the scene's.
pub(super) fn check_cohesion_boundaries(
    walls: &[Boundary],
    bodies: &[BodyInit],
    named: &Named,
    (contact, contact_map): (&ContactSpec, &Map<String, Value>),
    items: Option<&Value>,
) -> Result<(), FieldError> {
    for (k, w) in walls.iter().enumerate() {
        let kind = match (w.drum(), w.segment()) {
            (Some(_), _) => "a drum",
            (None, Some(_)) => "a segment wall",
            (None, None) => continue,
        };
        let own = items
            .and_then(|v| v.get(k))
            .is_some_and(|item| item.get("cohesion").is_some());
        // The first body that is not made of disks and meets this wall with cohesion.
        let offending = bodies.iter().enumerate().find(|(_, b)| {
            !matches!(b.shape, Shape::Circle { .. } | Shape::Clump(_))
                && match w.material {
                    None => w.spec.cohesion.is_some(),
                    Some(a) => named
                        .materials
                        .pair(contact, a, b.material)
                        .is_ok_and(|p| p.spec.cohesion.is_some()),
                }
        });
        let Some((i, body)) = offending else {
            continue;
        };
        let at = if own {
            join(&index("walls", k), "cohesion")
        } else {
            match w.material {
                Some(m) if m != 0 && named.map(contact_map, m).contains_key("cohesion") => {
                    join(&named.path(m), "cohesion")
                }
                _ => "contact.cohesion".to_string(),
            }
        };
        return Err(FieldError::new(
            at,
            format!(
                "cohesion is not available against {kind} (walls[{k}]) for bodies[{i}], of shape \
                 `{}`: only disks and clumps have a closed-form overlap area with it to pull on; give \
                 that wall a law without it (its own `\"cohesion\": 0`, or a material without \
                 cohesion)",
                body.shape.type_name()
            ),
        ));
    }
    Ok(())
}
