//! Thin entry point: parse the command line, execute it in the library, map
//! errors to exit codes (see `fibresim::error`).

use clap::Parser;

fn main() {
    let cli = fibresim::cli::Cli::parse();
    if let Err(e) = fibresim::cli::execute(cli) {
        eprintln!("error: {e}");
        std::process::exit(e.exit_code());
    }
}
