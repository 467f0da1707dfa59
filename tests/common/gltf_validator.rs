//! The Khronos glTF validator (the npm package `gltf-validator` under node, which `.ci/run`
//! installs) run on a `.glb`.

use std::path::Path;
use std::process::Command;

/// What the validator said of a file.
pub struct Validation {
    /// Whether it ran and found no error.
    pub passed: bool,
    /// Its summary: `{"errors":…,"warnings":…,"messages":[the first ten]}`.
    pub report: String,
}

/// Runs the validator on the `.glb` at `path` (up to 50 issues), printing its summary.
pub fn validate_glb(path: &Path) -> Validation {
    let root = Command::new("npm").args(["root", "-g"]).output().unwrap();
    let node_path = String::from_utf8_lossy(&root.stdout).trim().to_string();
    let script = format!(
        r#"
const validator = require('gltf-validator');
const bytes = new Uint8Array(require('fs').readFileSync({path:?}));
validator.validateBytes(bytes, {{ maxIssues: 50 }}).then((r) => {{
  console.log(JSON.stringify({{ errors: r.issues.numErrors, warnings: r.issues.numWarnings,
                                messages: r.issues.messages.slice(0, 10) }}));
  process.exit(r.issues.numErrors > 0 ? 1 : 0);
}}).catch((e) => {{ console.error('validator failed: ' + e); process.exit(2); }});
"#,
        path = path.display().to_string()
    );
    let out = Command::new("node")
        .env("NODE_PATH", &node_path)
        .args(["-e", &script])
        .output()
        .expect("node (and npm install -g gltf-validator, as .ci/run does)");
    let report = String::from_utf8_lossy(&out.stdout).to_string();
    println!(
        "validator ({}): {report}{}",
        path.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    Validation {
        passed: out.status.success(),
        report,
    }
}
