//! `ggx export SCENE --format mitsuba -o scene.xml`: the scene as another renderer's scene
//! file, meshes and environment map written beside it (see [`crate::mitsuba`]).

use std::io::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use ggx_film::OutputOptions;

use crate::args::{ExportArgs, ExportFormat, MeshFormatArg, OnOff};
use crate::exit::Outcome;
use crate::mitsuba::{self, ExportOptions, MeshFormat, SideContent};
use crate::{output, overrides};

/// Runs `ggx export`: loads the scene with the command line's overrides, refuses a material
/// without a twin, then writes the side files and last the XML (each atomically, so the XML
/// never names a file that is not there).
pub fn run(args: &ExportArgs) -> Result<Outcome> {
    let shown = args.output.display();
    if !args.output.extension().is_some_and(|e| e.eq_ignore_ascii_case("xml")) {
        bail!("{shown}: the Mitsuba scene file must end in .xml");
    }
    output::check_not_input(&args.output, &[&args.scene])?;
    ggx_film::check_file(&args.output)?;
    let limits = args.limits.limits();
    let mut scene = ggx_scene::load_scene_with(&args.scene, &limits)?;
    if let Some(frame) = args.frame {
        scene.set_frame(frame)?;
    }
    if let Some(spp) = args.spp {
        scene.integrator.spp = spp;
    }
    if let Some(seed) = args.seed {
        scene.integrator.seed = seed;
    }
    scene.camera.resolution = overrides::resolution(scene.camera.resolution, args.size.width, args.size.height)?;
    if let Some(on) = args.energy_compensation {
        scene.set_energy_compensation(on == OnOff::On);
    }
    // One format so far; a new one is a compile error here until it is handled.
    match args.format {
        ExportFormat::Mitsuba => {}
    }
    let stem = args.output.file_stem().map_or_else(|| "scene".to_owned(), |s| mitsuba::file_safe(&s.to_string_lossy()));
    let options = ExportOptions {
        stem,
        mesh_format: match args.mesh_format {
            MeshFormatArg::Ply => MeshFormat::Ply,
            MeshFormatArg::Obj => MeshFormat::Obj,
        },
        env_upsample: args.env_upsample,
        source: args.scene.display().to_string(),
    };
    let export = mitsuba::export(&scene, &options)?;

    let dir = args
        .output
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .map_or_else(|| PathBuf::from("."), Path::to_path_buf);
    let mut inputs: Vec<&Path> = scene.inputs.iter().map(PathBuf::as_path).collect();
    inputs.push(&args.scene);
    let paths: Vec<PathBuf> = export.files.iter().map(|f| dir.join(&f.name)).collect();
    for path in &paths {
        output::check_not_input(path, &inputs)?;
        ggx_film::check_file(path)?;
    }
    output::check_not_input(&args.output, &inputs)?;
    for (file, path) in export.files.iter().zip(&paths) {
        match &file.content {
            SideContent::Bytes(bytes) => ggx_film::write_file(path, bytes)?,
            SideContent::Image { width, height, pixels } => {
                ggx_film::write_image(path, *width, *height, pixels, &OutputOptions::default())?;
            }
        }
    }
    ggx_film::write_file(&args.output, export.xml.as_bytes())?;

    let mut out = std::io::stdout().lock();
    if !export.unused_materials.is_empty() {
        writeln!(out, "not exported (no triangle uses them): {}", export.unused_materials.join(", "))
            .context("cannot write to stdout")?;
    }
    let [w, h] = scene.camera.resolution;
    writeln!(
        out,
        "exported {} triangles, {} files, {w}x{h}, {} spp -> {shown}",
        scene.mesh.triangles.len(),
        export.files.len(),
        scene.integrator.spp
    )
    .context("cannot write to stdout")?;
    Ok(Outcome::Done)
}
