//! The LBP front end: a small pipeline language (grammar in `lbp.pest`) parsed into the
//! same syntax tree as RON, with every node's span; pest's errors become located diagnostics.

pub mod grammar;
mod nesting;
mod parse;
pub mod print;

use crate::diag::{Code, Diagnostic, Diagnostics};
use crate::ir::Pipeline;
use crate::span::{FileId, Span};
use pest::Parser;

#[derive(pest_derive::Parser)]
#[grammar = "front/lbp/lbp.pest"]
pub struct LbpParser;

/// Words for grammar rules in "expected ..." messages.
fn rule_word(r: &Rule) -> &'static str {
    match r {
        Rule::EOI => "end of file",
        Rule::colon => "`:`",
        Rule::equals => "`=`",
        Rule::open_brace => "`{`",
        Rule::close_brace => "`}`",
        Rule::open_paren => "`(`",
        Rule::close_paren => "`)`",
        Rule::pipeline_decl => "`pipeline NAME`",
        Rule::use_decl => "`use \"file\"`",
        Rule::fix => "`fix VARIANT = OPTION`",
        Rule::remove => "`remove KIND NAME`",
        Rule::remove_kind => "`pass`, `resource`, `param`, `sampler` or `variant`",
        Rule::replace => "`replace`",
        Rule::param => "`param`",
        Rule::sampler => "`sampler`",
        Rule::texture => "`texture`",
        Rule::buffer => "`buffer`",
        Rule::accel => "`acceleration_structure`",
        Rule::pass => "a pass (`raster`, `fullscreen`, `compute`)",
        Rule::template => "`template`",
        Rule::template_params => "template parameters `(a, b)`",
        Rule::like | Rule::like_word | Rule::template_ref => "`like TEMPLATE`",
        Rule::arg => "a template parameter `$NAME`",
        Rule::pass_kind => "`raster`, `fullscreen` or `compute`",
        Rule::variant => "`variant`",
        Rule::option => "`option`",
        Rule::output => "`output`",
        Rule::hdr_output => "`hdr_output`",
        Rule::name | Rule::dotted | Rule::ident => "a name",
        Rule::names | Rule::name_items => "names",
        Rule::match_head => "`match(VARIANT) {`",
        Rule::arm_key => "an option name (or `_`)",
        Rule::shader_arm
        | Rule::vertex_arm
        | Rule::fragment_arm
        | Rule::entry_arm
        | Rule::draw_arm
        | Rule::cull_arm
        | Rule::count_arm
        | Rule::color_arm
        | Rule::depth_arm
        | Rule::read_arm
        | Rule::name_arm
        | Rule::block_arm
        | Rule::bind_arm
        | Rule::per_light_arm
        | Rule::repeat_arm
        | Rule::set_arm
        | Rule::constants_arm
        | Rule::dispatch_arm => "an arm `option: value`",
        Rule::read_group | Rule::name_group | Rule::color_group => "`(a, b, ...)`",
        Rule::read_match | Rule::name_match | Rule::color_match => "a choice `match(VARIANT) { ... }`",
        Rule::light_kinds => "light kinds `(Point, Spot)`",
        Rule::string | Rule::doc => "a string",
        Rule::number => "a number",
        Rule::uint => "a whole number",
        Rule::bool => "`true` or `false`",
        Rule::tuple => "a tuple `(a, b, ...)`",
        Rule::value => "a value",
        Rule::param_type | Rule::enum_type => "a parameter type",
        Rule::range => "`in MIN..MAX`, `min V` or `max V`",
        Rule::size | Rule::fixed | Rule::viewport => "a size (`viewport`, `viewport*S` or `WxH`)",
        Rule::texture_opt | Rule::flag | Rule::layers | Rule::mips => "a texture option",
        Rule::buffer_opt => "a buffer option",
        Rule::per_light => "`per_light(...)`",
        Rule::sampler_opt | Rule::sampler_word | Rule::mipmap => "a sampler option",
        Rule::compare => "`compare`",
        Rule::vertex | Rule::fragment | Rule::entry => "an entry point",
        Rule::stage_ref => "an entry point name or \"file#entry\"",
        Rule::draw
        | Rule::cull
        | Rule::instances
        | Rule::multiview
        | Rule::color
        | Rule::depth
        | Rule::reads
        | Rule::writes
        | Rule::params
        | Rule::param_block
        | Rule::bind
        | Rule::when
        | Rule::per_face
        | Rule::dispatch
        | Rule::shader
        | Rule::constants
        | Rule::after
        | Rule::pass_per_light => "a pass property",
        Rule::constant => "`NAME = VALUE`",
        Rule::target | Rule::target_opt | Rule::clear | Rule::load | Rule::blend | Rule::layer | Rule::nowrite => "a target option",
        Rule::read | Rule::prev => "a resource or `prev(NAME)`",
        Rule::binding => "`shader_name = resource`",
        Rule::cond | Rule::not_cond | Rule::all_cond | Rule::any_cond | Rule::call_cond | Rule::reflective | Rule::blended => "a condition",
        Rule::groups | Rule::size_of => "`groups(x, y, z)` or `size(NAME)`",
        Rule::option_opt
        | Rule::requires
        | Rule::limit
        | Rule::limit_item
        | Rule::fallback
        | Rule::shaders
        | Rule::shader_sub
        | Rule::opt_jitter => "an option property",
        _ => "something else",
    }
}

fn syntax_error(file: FileId, text: &str, e: pest::error::Error<Rule>) -> Diagnostic {
    let (start, end) = match e.location {
        pest::error::InputLocation::Pos(p) => (p, p),
        pest::error::InputLocation::Span((a, b)) => (a, b),
    };
    // Point at the offending token (or the end of the file); at least its first character,
    // which may be several bytes long.
    let first = text[start..].chars().next().map_or(0, char::len_utf8);
    let tok_end = text[start..]
        .find(|c: char| c.is_whitespace() || "(){},:=".contains(c))
        .map(|n| start + n.max(first))
        .unwrap_or(text.len());
    let end = end.max(tok_end.min(text.len()));
    let found = if start >= text.len() {
        "end of file".to_string()
    } else {
        format!("`{}`", &text[start..end.max(start + first).min(text.len())])
    };
    let mut suggestion = None;
    let mut wants_brace = false;
    let mut wants_colon = false;
    let mut wants_tuple = false;
    let message = match &e.variant {
        pest::error::ErrorVariant::ParsingError { positives, .. } => {
            let mut words: Vec<&str> = vec![];
            for w in positives.iter().map(rule_word) {
                if w != "something else" && !words.contains(&w) {
                    words.push(w);
                }
            }
            // A misspelt keyword (`param` in a pass, `textur`): the keywords allowed here.
            let token = text.get(start..end).unwrap_or("");
            let keywords: Vec<&str> = positives.iter().filter_map(keyword).collect();
            wants_brace = positives.contains(&Rule::close_brace);
            wants_colon = positives.contains(&Rule::colon);
            wants_tuple = positives.contains(&Rule::tuple);
            suggestion = crate::diag::did_you_mean(token, keywords.iter().copied()).map(|k| format!("did you mean `{k}`?"));
            if words.is_empty() {
                format!("unexpected {found}")
            } else {
                format!("expected {}, found {found}", words.join(" or "))
            }
        }
        pest::error::ErrorVariant::CustomError { message } => message.clone(),
    };
    // A tuple that went wrong inside is reported at its `(`: say what it must hold, over all of it.
    let (message, end) = match malformed_tuple(text, start).filter(|_| wants_tuple) {
        Some(close) => (
            "expected numbers separated by commas in this tuple, e.g. `(0, 0, 0, 1)`".to_string(),
            close,
        ),
        None => (message, end),
    };
    let mut d = Diagnostic::error(Code::LbpSyntax, message, Span::new(file, start, end.max(start)));
    // A `}` was expected: show the `{` it would close, which may be far above.
    if wants_brace {
        if let Some(at) = nesting::unclosed_brace(&text[..start.min(text.len())]) {
            d = d.with_secondary(Span::new(file, at, at + 1), "this `{` is not closed");
        }
    }
    // `x: a, b, y: c` inside a choice: `b` read as the next arm's option, its `:` missing.
    if wants_colon && suggestion.is_none() && found != "`:`" && in_choice(&text[..start.min(text.len())]) {
        suggestion = Some("an arm of several elements writes them in parentheses: `x: (a, b), y: c`".to_string());
    }
    match suggestion {
        Some(s) => d.with_note(s),
        None => d,
    }
}

/// The end of the `( ... )` at `start` on its line (past its `)`), when there is one.
fn malformed_tuple(text: &str, start: usize) -> Option<usize> {
    let rest = text.get(start..)?.strip_prefix('(')?;
    let line = rest.split('\n').next()?;
    line.find(')').map(|i| start + 1 + i + 1)
}

/// Whether `before` ends inside a choice's arms (its innermost open `{` follows `match(..)`).
fn in_choice(before: &str) -> bool {
    nesting::unclosed_brace(before).is_some_and(|at| {
        let head = before[..at].trim_end();
        let line = head.rsplit('\n').next().unwrap_or(head);
        head.ends_with(')') && line.contains("match(")
    })
}

/// The keyword that starts a rule (items, pass properties), for suggestions and tree keys.
fn keyword(r: &Rule) -> Option<&'static str> {
    Some(match r {
        Rule::param => "param",
        Rule::sampler => "sampler",
        Rule::texture => "texture",
        Rule::buffer => "buffer",
        Rule::accel => "acceleration_structure",
        Rule::variant => "variant",
        Rule::option => "option",
        Rule::output => "output",
        Rule::hdr_output => "hdr_output",
        Rule::vertex => "vertex",
        Rule::fragment => "fragment",
        Rule::entry => "entry",
        Rule::draw => "draw",
        Rule::cull => "cull",
        Rule::instances => "instances",
        Rule::multiview => "multiview",
        Rule::color => "color",
        Rule::depth => "depth",
        Rule::reads => "reads",
        Rule::writes => "writes",
        Rule::params => "params",
        Rule::param_block => "param_block",
        Rule::bind => "bind",
        Rule::when => "when",
        Rule::per_light | Rule::pass_per_light => "per_light",
        Rule::shader => "shader",
        Rule::after => "after",
        Rule::constants => "constants",
        Rule::per_face => "per_face",
        Rule::shadow_casters => "shadow_casters",
        Rule::per_mip => "per_mip",
        Rule::repeat => "repeat",
        Rule::always => "always",
        Rule::set => "set",
        Rule::dispatch => "dispatch",
        _ => return None,
    })
}

/// Parse LBP text into the syntax tree. Syntax problems go to `diags`.
pub fn parse_tree(file: FileId, text: &str, diags: &mut Diagnostics) -> Option<crate::tree::Node> {
    if let Some((start, end)) = nesting::too_deep(text) {
        let msg = format!("nested more than {} levels deep", crate::front::MAX_NESTING);
        diags.push(Diagnostic::error(Code::NestingTooDeep, msg, Span::new(file, start, end)));
        return None;
    }
    let pairs = match LbpParser::parse(Rule::file, text) {
        Ok(p) => p,
        Err(e) => {
            diags.push(syntax_error(file, text, e));
            return None;
        }
    };
    let before = diags.error_count();
    let tree = parse::Builder {
        file,
        diags,
        text_len: text.len(),
    }
    .file(pairs);
    if diags.error_count() > before {
        return None;
    }
    tree
}

/// Parse LBP text already in the source map and lower it. Problems go to `diags`.
pub fn parse_pipeline(file: FileId, text: &str, diags: &mut Diagnostics) -> Option<Pipeline> {
    let tree = parse_tree(file, text, diags)?;
    crate::syntax::lower::pipeline(&tree, diags)
}
