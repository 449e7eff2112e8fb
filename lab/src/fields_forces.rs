//! `dem2d-lab fields-forces`: the figures and numbers of the guide's page
//! `docs/src/results/fields-forces.md` — the profiles of the sheared cell (`dem2d fields`) and
//! the distributions of the normal contact forces (`dem2d forces`) of relaxed (FIRE,
//! frictionless) and sheared packings of disks and of ellipses of aspect ratio 2, with the
//! exponent α of a fit `P(x) = A exp(−c x^α)` to each tail (x = f/⟨f⟩ ≥ 1).
//!
//! Runs, through the `dem2d` binary as a user would (about a minute on one core):
//! `dem2d run cases/shear_cell.json --contacts`, `dem2d run cases/shear_cell_ellipses.json
//! --contacts`, `dem2d run cases/compress_cell_mu0.json` and `cases/compress_cell_ellipses_mu0.json`
//! then `dem2d relax` of their end states; `dem2d fields SHEAR --bins 10 --from 0.4`; `dem2d
//! forces SHEAR --from 0.4 --bins 40` and `dem2d forces RELAXED --bins 20`.

use dem2d::output::plot::{self, Legend, LinePanel, Series};
use std::path::{Path, PathBuf};
use std::process::Command;

/// Where the figures go and where the runs go.
pub struct Options {
    pub cases: PathBuf,
    pub out: PathBuf,
    pub work: PathBuf,
}

fn dem2d(args: &[&str]) -> Result<String, String> {
    let exe = crate::dem2d_exe()?;
    let out = Command::new(&exe)
        .args(args)
        .output()
        .map_err(|e| format!("{}: {e}", exe.display()))?;
    if !out.status.success() {
        return Err(format!(
            "dem2d {}: {}{}",
            args.join(" "),
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    Ok(String::from_utf8_lossy(&out.stdout).into_owned())
}

/// A CSV file's columns by name (an empty field or NaN is NaN).
fn columns(path: &Path) -> Result<std::collections::HashMap<String, Vec<f64>>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut lines = text.lines();
    let names: Vec<String> = lines
        .next()
        .ok_or(format!("{}: empty", path.display()))?
        .split(',')
        .map(String::from)
        .collect();
    let mut out: std::collections::HashMap<String, Vec<f64>> =
        names.iter().map(|n| (n.clone(), Vec::new())).collect();
    for line in lines {
        for (n, v) in names.iter().zip(line.split(',')) {
            out.get_mut(n).unwrap().push(v.parse().unwrap_or(f64::NAN));
        }
    }
    Ok(out)
}

/// The fit `ln P = ln A − c x^α` to the bins of `forces.csv` with `x ≥ 1` and a count: for each
/// α on a grid of 0.01 from 0.5 to 4, the weighted least-squares line of ln P against x^α
/// (weights the counts, the inverse variance of ln P for Poisson counts); the α of the least
/// weighted residual. Returns (α, c, bins used).
pub fn fit_tail(x: &[f64], pdf: &[f64], count: &[f64]) -> (f64, f64, usize) {
    let pts: Vec<(f64, f64, f64)> = (0..x.len())
        .filter(|&k| x[k] >= 1.0 && count[k] > 0.0)
        .map(|k| (x[k], pdf[k].ln(), count[k]))
        .collect();
    let mut best = (f64::INFINITY, f64::NAN, f64::NAN);
    for step in 50..=400 {
        let alpha = step as f64 / 100.0;
        let w: f64 = pts.iter().map(|p| p.2).sum();
        let mu = pts.iter().map(|p| p.2 * p.0.powf(alpha)).sum::<f64>() / w;
        let ml = pts.iter().map(|p| p.2 * p.1).sum::<f64>() / w;
        let sxx: f64 = pts
            .iter()
            .map(|p| p.2 * (p.0.powf(alpha) - mu).powi(2))
            .sum();
        let sxy: f64 = pts
            .iter()
            .map(|p| p.2 * (p.0.powf(alpha) - mu) * (p.1 - ml))
            .sum();
        let slope = sxy / sxx;
        let res: f64 = pts
            .iter()
            .map(|p| p.2 * (p.1 - ml - slope * (p.0.powf(alpha) - mu)).powi(2))
            .sum();
        if res < best.0 {
            best = (res, alpha, -slope);
        }
    }
    (best.1, best.2, pts.len())
}

/// The exponent of the cumulative tail `C(x) = P[f/⟨f⟩ > x] ~ exp(−c x^α)` from the bins of
/// `forces.csv`: C at each bin's upper edge with `1 ≤ x ≤ 3` and C > 0, and the least-squares
/// slope of ln(−ln C) against ln x (1 for an exponential, 2 for a Gaussian tail).
pub fn fit_cumulative(x: &[f64], count: &[f64]) -> f64 {
    let total: f64 = count.iter().sum();
    let width = 2.0 * x[0];
    let mut above = total;
    let mut pts = Vec::new();
    for k in 0..x.len() {
        above -= count[k];
        let edge = x[k] + 0.5 * width;
        if (1.0..=3.0).contains(&edge) && above > 0.0 {
            pts.push((edge.ln(), (-(above / total).ln()).ln()));
        }
    }
    let n = pts.len() as f64;
    let (mx, my) = (
        pts.iter().map(|p| p.0).sum::<f64>() / n,
        pts.iter().map(|p| p.1).sum::<f64>() / n,
    );
    pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum::<f64>()
        / pts.iter().map(|p| (p.0 - mx).powi(2)).sum::<f64>()
}

/// Runs the cases, writes `fields_profiles.svg` and `forces_pdf.svg` into `out` (PNG copies in
/// `work`), and returns the report printed on the terminal.
pub fn fields_forces(opts: &Options) -> Result<String, String> {
    std::fs::create_dir_all(&opts.work).map_err(|e| format!("{}: {e}", opts.work.display()))?;
    std::fs::create_dir_all(&opts.out).map_err(|e| format!("{}: {e}", opts.out.display()))?;
    let case = |name: &str| opts.cases.join(name).to_string_lossy().into_owned();
    let work = |name: &str| opts.work.join(name).to_string_lossy().into_owned();
    let mut report = String::new();
    // The sheared cells, with their contacts.
    for (name, file) in [
        ("shear_disks", "shear_cell.json"),
        ("shear_ellipses", "shear_cell_ellipses.json"),
    ] {
        eprintln!("fields-forces: dem2d run {file}");
        dem2d(&[
            "run",
            &case(file),
            "--out",
            &work(name),
            "--contacts",
            "--quiet",
            "--overwrite",
        ])?;
        dem2d(&["forces", &work(name), "--from", "0.4", "--bins", "40"])?;
    }
    dem2d(&[
        "fields",
        &work("shear_disks"),
        "--bins",
        "10",
        "--from",
        "0.4",
    ])?;
    // The relaxed packings.
    for (name, file) in [
        ("relaxed_disks", "compress_cell_mu0.json"),
        ("relaxed_ellipses", "compress_cell_ellipses_mu0.json"),
    ] {
        eprintln!("fields-forces: dem2d run {file}, dem2d relax");
        let comp = format!("{}_compressed", work(name));
        dem2d(&["run", &case(file), "--out", &comp, "--quiet", "--overwrite"])?;
        let state = format!("{comp}/state.json");
        let _ = std::fs::remove_dir_all(work(name));
        dem2d(&["relax", &state, "--out", &work(name), "--quiet"])?;
        dem2d(&["forces", &work(name), "--bins", "20"])?;
    }

    // The profiles of the sheared disks.
    let f = columns(&opts.work.join("shear_disks/fields.csv"))?;
    let ys = &f["y"];
    let n = ys.len() as f64;
    let (my, mv) = (ys.iter().sum::<f64>() / n, f["vx"].iter().sum::<f64>() / n);
    let slope = ys
        .iter()
        .zip(&f["vx"])
        .map(|(y, v)| (y - my) * (v - mv))
        .sum::<f64>()
        / ys.iter().map(|y| (y - my).powi(2)).sum::<f64>();
    let mean = |c: &str| f[c].iter().sum::<f64>() / n;
    let temps = &f["temperature"];
    let inner = &temps[1..temps.len() - 1];
    let last = ys.len() - 1;
    let phis = &f["phi"];
    report.push_str(&format!(
        "sheared disks (dem2d fields {} --bins 10 --from 0.4): {} frames; dvx/dy = {slope:.3} /s \
         (imposed 3 /s); mean phi = {:.4} (slabs from {:.4} to {:.4}); mean sxy = {:.1} dyn/cm, \
         mean syy = {:.1} dyn/cm, slabs' -sxy/syy from {:.3} to {:.3}; T from {:.1} to {:.1} \
         cm²/s² but {:.1} and {:.1} in the two slabs at the seam; vx of the top slab {:.1} cm/s \
         against the imposed {:.1} (gamma_dot L_y = {:.1} cm/s)\n",
        work("shear_disks"),
        f["frames"][0],
        mean("phi"),
        phis.iter().copied().fold(f64::INFINITY, f64::min),
        phis.iter().copied().fold(0.0, f64::max),
        mean("sxy"),
        mean("syy"),
        (0..ys.len())
            .map(|k| -f["sxy"][k] / f["syy"][k])
            .fold(f64::INFINITY, f64::min),
        (0..ys.len())
            .map(|k| -f["sxy"][k] / f["syy"][k])
            .fold(0.0, f64::max),
        inner.iter().copied().fold(f64::INFINITY, f64::min),
        inner.iter().copied().fold(0.0, f64::max),
        temps[0],
        temps[last],
        f["vx"][last],
        3.0 * (ys[last] - my),
        3.0 * 2.0 * my,
    ));
    let profile = |col: &str, title: &str, label: &str, color: usize| {
        let points: Vec<(f64, f64)> = ys.iter().zip(&f[col]).map(|(y, v)| (*y, *v)).collect();
        let mut s = Series::line(title, points, color);
        s.markers = true;
        LinePanel {
            title: title.into(),
            x_label: "y (cm)".into(),
            y_label: label.into(),
            series: vec![s],
            legend: Legend::UpperLeft,
            ..Default::default()
        }
    };
    let mut vx = profile("vx", "mean velocity vx", "vx (cm/s)", 0);
    let (y0, y1) = (ys[0] - 0.6, ys[ys.len() - 1] + 0.6);
    vx.series.push(Series::line(
        "imposed γ̇ (y − Ly/2), γ̇ = 3 /s",
        vec![(y0, 3.0 * (y0 - my)), (y1, 3.0 * (y1 - my))],
        3,
    ));
    let mut sxy = profile("sxy", "shear stress σxy", "σxy (dyn/cm)", 2);
    sxy.series.push(Series::line(
        "syy",
        ys.iter().zip(&f["syy"]).map(|(y, v)| (*y, *v)).collect(),
        4,
    ));
    sxy.series[0].label = "σxy".into();
    sxy.series[1].label = "σyy".into();
    sxy.title = "stress σxy and σyy".into();
    sxy.y_label = "stress (dyn/cm)".into();
    let mut phi = profile("phi", "packing fraction φ", "φ", 1);
    phi.y_range = Some((0.7, 0.85));
    let temp = profile("temperature", "granular temperature T", "T (cm²/s²)", 5);
    let mut panels = vec![vx, phi, temp, sxy];
    for p in &mut panels {
        p.legend = Legend::Auto;
    }
    panels[3].y_range = Some((-500.0, 1400.0));
    panels[3].legend = Legend::UpperRight;
    let svg = opts.out.join("fields_profiles.svg");
    plot::line_panels(&svg, (1000, 700), (2, 2), &panels).map_err(|e| e.to_string())?;
    let mut written = vec![svg];

    // The force distributions.
    let mut fits = Vec::new();
    let mut force_panels = Vec::new();
    for (shape, relaxed, sheared) in [
        ("disks", "relaxed_disks", "shear_disks"),
        (
            "ellipses, aspect ratio 2",
            "relaxed_ellipses",
            "shear_ellipses",
        ),
    ] {
        let mut series = Vec::new();
        for (k, (name, what, bins)) in [
            (relaxed, "relaxed (FIRE, μ = 0)", 20),
            (sheared, "sheared (μ = 0.4, t ≥ 0.4 s)", 40),
        ]
        .into_iter()
        .enumerate()
        {
            let c = columns(&opts.work.join(name).join("forces.csv"))?;
            let j: serde_json::Value = serde_json::from_str(
                &std::fs::read_to_string(opts.work.join(name).join("forces.json"))
                    .map_err(|e| e.to_string())?,
            )
            .map_err(|e| e.to_string())?;
            let (alpha, cc, used) = fit_tail(&c["f_over_mean"], &c["pdf"], &c["count"]);
            let cumulative = fit_cumulative(&c["f_over_mean"], &c["count"]);
            let from = if k == 0 { "" } else { " --from 0.4" };
            let total: f64 = c["count"].iter().sum();
            // (From +0: an empty f64 sum is −0.)
            let above = (0..c["count"].len())
                .filter(|&i| c["f_over_mean"][i] > 3.0)
                .map(|i| c["count"][i])
                .fold(0.0, |a, b| a + b);
            fits.push(format!(
                "{shape}, {what} (dem2d forces {}{from} --bins {bins}): {} contacts, max \
                 f/<f> = {:.2}, share in the bins centred above 3 = {:.4} (exponential: \
                 {:.4}); fit P = A exp(-c x^alpha) over the {used} bins with x >= 1: alpha = \
                 {alpha:.2}, c = {cc:.2}; cumulative tail over 1 <= x <= 3: alpha = \
                 {cumulative:.2}\n",
                work(name),
                j["contacts"],
                // The bins span 0 to the largest force: the last centre and a half width.
                c["f_over_mean"][c["f_over_mean"].len() - 1] + c["f_over_mean"][0],
                above / total,
                (-3f64).exp(),
            ));
            let points: Vec<(f64, f64)> = (0..c["pdf"].len())
                .filter(|&i| c["count"][i] > 0.0)
                .map(|i| (c["f_over_mean"][i], c["pdf"][i]))
                .collect();
            let mut s = Series::line(format!("{what}: α = {alpha:.2}"), points, k);
            s.markers = true;
            series.push(s);
        }
        let x: Vec<(f64, f64)> = (0..=80)
            .map(|i| i as f64 * 0.1)
            .map(|x| (x, (-x).exp()))
            .collect();
        series.push(Series::line("exponential e^(−x)", x, 3));
        force_panels.push(LinePanel {
            title: format!("P(f/⟨f⟩), {shape}"),
            x_label: "x = f / ⟨f⟩".into(),
            y_label: "probability density P(x)".into(),
            log_y: true,
            series,
            x_range: Some((0.0, 8.0)),
            y_range: Some((1e-4, 3.0)),
            legend: Legend::UpperRight,
            ..Default::default()
        });
    }
    for f in &fits {
        report.push_str(f);
    }
    let svg = opts.out.join("forces_pdf.svg");
    plot::line_panels(&svg, (1000, 480), (1, 2), &force_panels).map_err(|e| e.to_string())?;
    written.push(svg);
    let png_dir = opts.work.join("png");
    std::fs::create_dir_all(&png_dir).map_err(|e| e.to_string())?;
    for svg in written {
        let text = std::fs::read_to_string(&svg).map_err(|e| e.to_string())?;
        let png = png_dir.join(svg.with_extension("png").file_name().unwrap());
        std::fs::write(&png, plot::png_of_svg(&text, 2.0)?).map_err(|e| e.to_string())?;
        report.push_str(&format!("{}\n{}\n", svg.display(), png.display()));
    }
    Ok(report)
}
