//! Thin entry point: parse the command line, execute it in the library, map
//! errors to exit codes (see `fibresim::error`).

use clap::Parser;

fn main() {
    let cli = fibresim::cli::Cli::parse();
    let result = fibresim::cli::execute(cli);
    #[cfg(feature = "replay")]
    fibresim::contact::replay::finish();
    if let Err(e) = result {
        eprintln!("error: {e}");
        std::process::exit(e.exit_code());
    }
}
