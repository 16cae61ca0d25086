//! afl target `environment`: see `avs_fuzz::environment`.

fn main() {
    afl::fuzz!(|data: &[u8]| avs_fuzz::environment(data));
}
