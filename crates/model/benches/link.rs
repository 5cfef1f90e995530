//! The cost of the link element against the detailed joint it stands for:
//! the reference joint (configs/paper.toml) and its calibrated link
//! (examples/link/link.toml, integrated to 1e-10 in steps of at most 0.05 sqrt(m/k) as every run of links
//! is) on the paper's deck under the whole of Corralitos 090, one thread,
//! each the fastest of three:
//!
//!     cargo bench -p quakejoint-model --bench link

use std::path::{Path, PathBuf};

use quakejoint_model::run::RunResult;
use quakejoint_model::Config;

fn fastest(base_dir: &Path, config: &Config) -> (f64, RunResult) {
    quakejoint_model::verification::fastest_run(base_dir, config, 3).expect("run")
}

fn main() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let paper_text = std::fs::read_to_string(root.join("configs/paper.toml")).expect("configs/paper.toml");
    let paper = Config::from_toml(&paper_text, "configs/paper.toml").expect("paper config");
    let link = std::fs::read_to_string(root.join("examples/link/link.toml")).expect("examples/link/link.toml");
    let table = &link[link.find("[joint.link]").expect("a [joint.link] table")..];
    let text = format!("{}\n{table}", paper_text.replacen("[joint]\n", "[joint]\nmodel = \"link\"\n", 1));
    let linked = Config::from_toml(&text, "paper with its link").expect("link config");
    let (t1, r1) = fastest(&root.join("configs"), &paper);
    let (t2, r2) = fastest(&root.join("configs"), &linked);
    println!("{:<44} {:>9} {:>7} {:>9}", "run", "time [s]", "steps", "Sa");
    println!("{:<44} {:>9.3} {:>7} {:>9.5}", "reference joint (307 bodies)", t1, r1.stats.steps, r1.sa);
    println!("{:<44} {:>9.3} {:>7} {:>9.5}", "its link element (1e-10, short steps)", t2, r2.stats.steps, r2.sa);
    println!("ratio {:.0}", t1 / t2);
}
