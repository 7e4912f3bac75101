//! gridplan's task runner. The experiment runner arrives with its own issue.

fn main() {
    eprintln!("usage: cargo xtask experiment <config.toml> (coming with the runner)");
    std::process::exit(2);
}
