//! `bench.csv`: one line per rendered rung (RFC 4180 quoting where a field needs it).

use super::ladder::Series;

/// The header line.
pub const HEADER: &str = "scene,config,axis,backend,spp,seconds,rmse,rel_mse,rel_mse_trimmed,camera_samples,rays";

/// A field, quoted when it holds a comma, a quote or a line break.
pub(crate) fn field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) { format!("\"{}\"", s.replace('"', "\"\"")) } else { s.to_string() }
}

/// The whole file: [`HEADER`], then every rung of every scene's series in order.
pub fn format(scenes: &[(String, Vec<Series>)]) -> String {
    let mut out = format!("{HEADER}\n");
    for (scene, series) in scenes {
        for s in series {
            for r in &s.rungs {
                out.push_str(&format!(
                    "{},{},{},{},{},{:.6},{:.6e},{:.6e},{:.6e},{},{}\n",
                    field(scene),
                    s.config.name(),
                    s.config.axis().name(),
                    s.config.backend.name(),
                    r.spp,
                    r.seconds,
                    r.rmse,
                    r.rel_mse,
                    r.rel_mse_trimmed,
                    r.camera_samples,
                    r.rays
                ));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::super::configs::{BASELINE, Config};
    use super::super::ladder::Rung;
    use super::*;
    use crate::render::Backend;

    #[test]
    fn lines() {
        let rung = Rung {
            spp: 4,
            seconds: 0.0123456789,
            rmse: 0.5,
            rel_mse: 1.25e-3,
            rel_mse_trimmed: 1e-3,
            camera_samples: 4096,
            rays: 9000,
        };
        let wgpu = Config { backend: Backend::Wgpu, ..BASELINE };
        let scenes = vec![
            ("cornell".to_string(), vec![Series { config: BASELINE, rungs: vec![rung] }]),
            ("a,\"b\"".to_string(), vec![Series { config: wgpu, rungs: vec![rung] }]),
        ];
        let text = format(&scenes);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], HEADER);
        assert_eq!(
            lines[1],
            "cornell,vndf-mis-sobol-cpu-spec,baseline,cpu,4,0.012346,5.000000e-1,1.250000e-3,1.000000e-3,4096,9000"
        );
        assert_eq!(
            lines[2],
            "\"a,\"\"b\"\"\",vndf-mis-sobol-wgpu-spec,backend,wgpu,4,0.012346,5.000000e-1,1.250000e-3,1.000000e-3,4096,9000"
        );
        assert_eq!(lines.len(), 3);
        assert!(text.ends_with('\n'));
    }
}
