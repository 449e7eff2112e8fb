//! `analysis.csv` (the measures of [`crate::analysis`] at each output frame) and `contacts.csv`
//! (every contact at each output frame, so that a run can be analysed again from its files,
//! with the walls of `walls.csv`, [`super::walls`]), and the reader of `contacts.csv` for
//! `dem2d analyze`.
//!
//! - `analysis.csv`: [`ANALYSIS_HEADER`]; stresses in dyn/cm², compression positive, angles in
//!   degrees; empty fields are NaN (no wall box, no elongated body, no contact).
//! - `contacts.csv`: `step,t,i,j,px,py,nx,ny,fn,ft,depth,state` — i the giver (a body index, or
//!   `w<k>` for wall k), j the receiving body, the point (cm), the unit normal from i to j, the
//!   normal and tangential force on j (dyn per cm of thickness: `F·n`, `F·t` with
//!   `t = (−n_y, n_x)`), the couple on j (dyn·cm per cm; its opposite on i: zero but for the
//!   area law's deep, four-crossing overlaps, whose force acts at the crossings' mean with this
//!   couple — a body's torque is `Σ (p − x) × F + couple`), the overlap δ (cm) and the
//!   geometry state. Runs written before the couple have no `couple` column (read as 0).

use super::trace::{LineFile, WriteError};
use crate::analysis::{self, Frame, FrameContact, Measures, Window};
use crate::dynamics::{Partner, World};
use crate::geometry::Vec2;
use crate::run::time::time_text;
use crate::run::{End, Moment, Observer, ObserverError, Plan, StepInfo};
use std::path::Path;

pub const ANALYSIS_HEADER: &str = "t,area,sxx,syy,sxy,p,q,q_over_p,boundary_sxx,boundary_syy,\
boundary_sxy,packing_fraction,z,z_no_rattlers,rattler_fraction,a_c,theta_c,a_n,theta_n,a_t,\
theta_t,orientation_order,bodies,contacts";
/// `analysis.csv`'s header in a periodic cell: [`ANALYSIS_HEADER`] and the cell's measures
/// ([`crate::analysis::CellMeasures`]).
pub const ANALYSIS_HEADER_CELL: &str = "t,area,sxx,syy,sxy,p,q,q_over_p,boundary_sxx,\
boundary_syy,boundary_sxy,packing_fraction,z,z_no_rattlers,rattler_fraction,a_c,theta_c,a_n,\
theta_n,a_t,theta_t,orientation_order,bodies,contacts,pressure,shear_stress,mu_eff,\
inertial_number,cell_ly";
pub const CONTACTS_HEADER: &str = "step,t,i,j,px,py,nx,ny,fn,ft,couple,depth,state";
/// The header of runs written before the couple was recorded.
pub const CONTACTS_HEADER_NO_COUPLE: &str = "step,t,i,j,px,py,nx,ny,fn,ft,depth,state";

/// A number, or nothing for NaN.
fn num(x: f64) -> String {
    if x.is_nan() {
        String::new()
    } else {
        format!("{x}")
    }
}

/// One row of `analysis.csv`.
pub fn analysis_row(t: &str, m: &Measures) -> String {
    let [sxx, syy, sxy] = m.stress;
    let (s1, s3, _) = analysis::stress::principal(m.stress);
    let (p, q) = (0.5 * (s1 + s3), 0.5 * (s1 - s3));
    let f = &m.fabric;
    let deg = |x: f64| x.to_degrees();
    [
        t.to_string(),
        num(m.area),
        num(sxx),
        num(syy),
        num(sxy),
        num(p),
        num(q),
        // q/p is undefined without a mean stress (an empty field, not `inf`).
        num(if p != 0.0 { q / p } else { f64::NAN }),
        num(m.boundary_stress[0]),
        num(m.boundary_stress[1]),
        num(m.boundary_stress[2]),
        num(m.packing_fraction),
        num(m.coordination),
        num(m.coordination_no_rattlers),
        num(m.rattler_fraction),
        num(f.a_c),
        num(deg(f.theta_c)),
        num(f.a_n),
        num(deg(f.theta_n)),
        num(f.a_t),
        num(deg(f.theta_t)),
        num(m.orientation_order),
        m.bodies.to_string(),
        m.contacts.to_string(),
    ]
    .into_iter()
    .chain(m.cell.into_iter().flat_map(|c| {
        [
            num(c.pressure),
            num(c.shear_stress),
            num(c.mu_eff),
            num(c.inertial_number),
            num(c.ly),
        ]
    }))
    .collect::<Vec<_>>()
    .join(",")
}

/// `analysis.csv`'s header: with the cell's measures in a periodic cell.
pub fn analysis_header(cell: bool) -> &'static str {
    if cell {
        ANALYSIS_HEADER_CELL
    } else {
        ANALYSIS_HEADER
    }
}

/// The writers of a run's analysis outputs (each optional); as an observer of a run, at the
/// trajectory's frames (the first, every `every` steps, the last — not a non-finite one).
pub struct AnalysisOutput {
    analysis: Option<LineFile>,
    contacts: Option<LineFile>,
    window: Option<Window>,
    last_step: Option<u64>,
    every: u64,
}

impl AnalysisOutput {
    /// Creates `analysis.csv` when `analysis`, `contacts.csv` when `contacts`, in
    /// `dir`; `window` the region of the measures (default: the periodic cell, the wall box,
    /// else the bodies' extent); `cell`: the scene has a periodic cell (its measures added); as
    /// an observer it writes every `every` steps.
    pub fn create(
        dir: &Path,
        analysis: bool,
        contacts: bool,
        window: Option<Window>,
        cell: bool,
        every: u64,
    ) -> Result<Self, WriteError> {
        let open = |on: bool, name: &str, header: &str| -> Result<Option<LineFile>, WriteError> {
            if !on {
                return Ok(None);
            }
            let mut f = LineFile::create(&dir.join(name))?;
            f.line(format_args!("{header}"))?;
            Ok(Some(f))
        };
        let a = open(analysis, "analysis.csv", analysis_header(cell))?;
        let c = open(contacts, "contacts.csv", CONTACTS_HEADER)?;
        Ok(AnalysisOutput {
            analysis: a,
            contacts: c,
            window,
            last_step: None,
            every: every.max(1),
        })
    }

    /// Writes the frame of the world's current state, labelled `step` (once per label). Reads
    /// the contact extras (normals, depths), which the step does not keep: the caller refreshes
    /// them ([`World::refresh_contact_extras`]; a run's driver does when
    /// [`Observer::reads_extras`] asks).
    pub fn write(&mut self, world: &World, step: u64) -> Result<(), WriteError> {
        if self.last_step == Some(step) {
            return Ok(());
        }
        self.last_step = Some(step);
        let frame = Frame::from_world(world);
        let t = time_text(step, world.dt);
        if let Some(a) = &mut self.analysis {
            let m = analysis::measure(&frame, self.window);
            a.line(format_args!("{}", analysis_row(&t, &m)))?;
        }
        if let Some(c) = &mut self.contacts {
            for k in &frame.contacts {
                let i = match k.i {
                    Partner::Body(b) => b.to_string(),
                    Partner::Wall(w) => format!("w{w}"),
                };
                c.line(format_args!(
                    "{step},{t},{i},{},{},{},{},{},{},{},{},{},{}",
                    k.j,
                    k.point.x,
                    k.point.y,
                    k.normal.x,
                    k.normal.y,
                    k.normal_force(),
                    k.tangential_force(),
                    k.couple,
                    k.depth,
                    k.state
                ))?;
            }
        }
        Ok(())
    }

    pub fn flush(&mut self) -> Result<(), WriteError> {
        if let Some(a) = &mut self.analysis {
            a.flush()?;
        }
        if let Some(c) = &mut self.contacts {
            c.flush()?;
        }
        Ok(())
    }
}

impl Observer for AnalysisOutput {
    fn reads_extras(&self, moment: Moment) -> bool {
        moment.writes_frame(self.every, self.last_step)
    }

    fn start(&mut self, world: &World, _: &Plan) -> Result<(), ObserverError> {
        Ok(self.write(world, world.step)?)
    }

    fn after_step(&mut self, world: &World, info: &StepInfo) -> Result<(), ObserverError> {
        if !info.blowup && info.step.is_multiple_of(self.every) {
            self.write(world, info.step)?;
        }
        Ok(())
    }

    fn finish(&mut self, world: &World, end: &End) -> Result<(), ObserverError> {
        if end.finite {
            self.write(world, end.step)?;
        }
        Ok(self.flush()?)
    }
}

/// Contacts of each output step, read back from `contacts.csv`.
#[derive(Clone, Debug, Default)]
pub struct ContactFrames {
    /// `(step, contacts)` in file order.
    pub contacts: Vec<(u64, Vec<FrameContact>)>,
}

/// Reads `contacts.csv` of a run directory. Errors name the file and the line.
pub fn read_contact_frames(dir: &Path) -> Result<ContactFrames, String> {
    let file = dir.join("contacts.csv");
    let text = std::fs::read_to_string(&file).map_err(|e| {
        format!(
            "{}: cannot read: {e} (the run has no per-contact data: run it again with \
             `dem2d run --contacts`, or \"output\": {{\"contacts\": true}} in the case)",
            file.display()
        )
    })?;
    let mut out = ContactFrames::default();
    // A last line cut short (a run stopped while writing) is left out; so is its frame's
    // trajectory row, which `RunData` leaves out.
    let mut lines = super::run_data::whole_lines(&text).0.lines();
    let bad = |n: usize, m: &str| format!("{}: line {n}: {m}", file.display());
    let width = match lines.next() {
        Some(CONTACTS_HEADER) => 13,
        Some(CONTACTS_HEADER_NO_COUPLE) => 12,
        _ => return Err(bad(1, &format!("expected the header `{CONTACTS_HEADER}`"))),
    };
    for (k, line) in lines.enumerate() {
        let f: Vec<&str> = line.split(',').collect();
        if f.len() != width {
            return Err(bad(k + 2, &format!("{} fields, expected {width}", f.len())));
        }
        // The fields after `ft`: the couple (when written), the depth, the state.
        let rest = width - 3;
        let x = |i: usize| {
            f[i].parse::<f64>()
                .map_err(|e| bad(k + 2, &format!("field {}: not a number: {e}", i + 1)))
        };
        let step: u64 = f[0]
            .parse()
            .map_err(|e| bad(k + 2, &format!("step: {e}")))?;
        let i = match f[2].strip_prefix('w') {
            Some(w) => Partner::Wall(w.parse().map_err(|e| bad(k + 2, &format!("i: {e}")))?),
            None => Partner::Body(f[2].parse().map_err(|e| bad(k + 2, &format!("i: {e}")))?),
        };
        let j: usize = f[3].parse().map_err(|e| bad(k + 2, &format!("j: {e}")))?;
        let normal = Vec2::new(x(6)?, x(7)?);
        let (fn_, ft) = (x(8)?, x(9)?);
        let c = FrameContact {
            i,
            j,
            point: Vec2::new(x(4)?, x(5)?),
            normal,
            force: normal * fn_ + Vec2::new(-normal.y, normal.x) * ft,
            couple: if width == 13 { x(10)? } else { 0.0 },
            depth: x(rest + 1)?,
            state: f[rest + 2].to_string(),
        };
        if out.contacts.last().is_none_or(|(s, _)| *s != step) {
            out.contacts.push((step, Vec::new()));
        }
        out.contacts.last_mut().expect("pushed").1.push(c);
    }
    Ok(out)
}
