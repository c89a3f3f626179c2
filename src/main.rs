//! The `critspeed` command; everything happens in [`critspeed::cli`].

fn main() -> std::process::ExitCode {
    critspeed::cli::main()
}
