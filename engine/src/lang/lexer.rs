//! Tokens of one block. The lexer works on the upper-cased text of a block whose comments have
//! already been blanked out, so columns stay those of the source line.

use super::ast::Func;

#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Tok {
    Letter(u8),
    Num { value: f64, point: bool },
    Hash,
    LBracket,
    RBracket,
    Comma,
    Assign,
    Plus,
    Minus,
    Star,
    Slash,
    Kw(Kw),
    /// A character that has no place in NC text.
    Bad(u8),
    /// Two decimal points in one number.
    BadNumber,
    Eof,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Kw {
    If,
    Goto,
    Then,
    While,
    Do,
    End,
    Eq,
    Ne,
    Gt,
    Ge,
    Lt,
    Le,
    And,
    Or,
    Xor,
    Mod,
    Func(Func),
    Atan,
    Pow,
    Popen,
    Pclos,
    Dprnt,
    Bprnt,
}

/// Keywords, longest first so that a prefix match takes the longest one.
const KEYWORDS: &[(&[u8], Kw)] = &[
    (b"ROUND", Kw::Func(Func::Round)),
    (b"WHILE", Kw::While),
    (b"POPEN", Kw::Popen),
    (b"PCLOS", Kw::Pclos),
    (b"DPRNT", Kw::Dprnt),
    (b"BPRNT", Kw::Bprnt),
    (b"GOTO", Kw::Goto),
    (b"THEN", Kw::Then),
    (b"ASIN", Kw::Func(Func::Asin)),
    (b"ACOS", Kw::Func(Func::Acos)),
    (b"ATAN", Kw::Atan),
    (b"SQRT", Kw::Func(Func::Sqrt)),
    (b"AND", Kw::And),
    (b"XOR", Kw::Xor),
    (b"MOD", Kw::Mod),
    (b"SIN", Kw::Func(Func::Sin)),
    (b"COS", Kw::Func(Func::Cos)),
    (b"TAN", Kw::Func(Func::Tan)),
    (b"ABS", Kw::Func(Func::Abs)),
    (b"BIN", Kw::Func(Func::Bin)),
    (b"BCD", Kw::Func(Func::Bcd)),
    (b"FIX", Kw::Func(Func::Fix)),
    (b"FUP", Kw::Func(Func::Fup)),
    (b"EXP", Kw::Func(Func::Exp)),
    (b"POW", Kw::Pow),
    (b"ADP", Kw::Func(Func::Adp)),
    (b"END", Kw::End),
    (b"IF", Kw::If),
    (b"DO", Kw::Do),
    (b"EQ", Kw::Eq),
    (b"NE", Kw::Ne),
    (b"GT", Kw::Gt),
    (b"GE", Kw::Ge),
    (b"LT", Kw::Lt),
    (b"LE", Kw::Le),
    (b"OR", Kw::Or),
    (b"LN", Kw::Func(Func::Ln)),
];

pub(super) struct Lexer<'a> {
    text: &'a [u8],
    pos: usize,
    /// Column of `text[0]` in the source line (1-based).
    col0: u32,
    peeked: Option<(Tok, u32)>,
}

impl<'a> Lexer<'a> {
    pub fn new(text: &'a [u8], col0: u32) -> Self {
        Lexer { text, pos: 0, col0, peeked: None }
    }

    /// The raw bytes not yet consumed (used by DPRNT, whose argument is text).
    pub fn rest(&mut self) -> &'a [u8] {
        if let Some((_, col)) = self.peeked.take() {
            self.pos = (col - self.col0) as usize;
        }
        &self.text[self.pos..]
    }

    pub fn advance_raw(&mut self, n: usize) {
        debug_assert!(self.peeked.is_none());
        self.pos += n;
    }

    /// The column of the next token.
    pub fn col(&mut self) -> u32 {
        self.peek().1
    }

    pub fn peek(&mut self) -> (Tok, u32) {
        if self.peeked.is_none() {
            let t = self.lex();
            self.peeked = Some(t);
        }
        self.peeked.expect("just filled")
    }

    pub fn next_tok(&mut self) -> (Tok, u32) {
        let t = self.peek();
        self.peeked = None;
        t
    }

    fn lex(&mut self) -> (Tok, u32) {
        let t = self.text;
        while self.pos < t.len() && (t[self.pos] == b' ' || t[self.pos] == b'\t' || t[self.pos] == b'\r') {
            self.pos += 1;
        }
        let col = self.col0 + self.pos as u32;
        let Some(&c) = t.get(self.pos) else {
            return (Tok::Eof, col);
        };
        let tok = match c {
            b'A'..=b'Z' => return (self.letters(), col),
            b'0'..=b'9' | b'.' => return (self.number(), col),
            b'#' => Tok::Hash,
            b'[' => Tok::LBracket,
            b']' => Tok::RBracket,
            b',' => Tok::Comma,
            b'=' => Tok::Assign,
            b'+' => Tok::Plus,
            b'-' => Tok::Minus,
            b'*' => Tok::Star,
            b'/' => Tok::Slash,
            other => Tok::Bad(other),
        };
        self.pos += 1;
        (tok, col)
    }

    fn letters(&mut self) -> Tok {
        let t = self.text;
        let start = self.pos;
        let mut end = start;
        while end < t.len() && t[end].is_ascii_uppercase() {
            end += 1;
        }
        if end - start >= 2 {
            let run = &t[start..end];
            for (word, kw) in KEYWORDS {
                if run.starts_with(word) {
                    self.pos += word.len();
                    return Tok::Kw(*kw);
                }
            }
        }
        self.pos += 1;
        Tok::Letter(t[start])
    }

    fn number(&mut self) -> Tok {
        let t = self.text;
        let start = self.pos;
        let mut points = 0;
        while self.pos < t.len() && (t[self.pos].is_ascii_digit() || t[self.pos] == b'.') {
            if t[self.pos] == b'.' {
                points += 1;
            }
            self.pos += 1;
        }
        if points > 1 {
            return Tok::BadNumber;
        }
        let s = std::str::from_utf8(&t[start..self.pos]).unwrap_or("0");
        // "." alone is zero with a decimal point, as FANUC reads `X.`.
        let value = if s == "." { 0.0 } else { s.parse::<f64>().unwrap_or(0.0) };
        Tok::Num { value, point: points == 1 }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn toks(s: &str) -> Vec<Tok> {
        let mut l = Lexer::new(s.as_bytes(), 1);
        let mut v = vec![];
        loop {
            let (t, _) = l.next_tok();
            if t == Tok::Eof {
                return v;
            }
            v.push(t);
        }
    }

    #[test]
    fn keywords_and_letters() {
        assert_eq!(
            toks("IF[#1GE2]GOTO10"),
            vec![
                Tok::Kw(Kw::If),
                Tok::LBracket,
                Tok::Hash,
                Tok::Num { value: 1.0, point: false },
                Tok::Kw(Kw::Ge),
                Tok::Num { value: 2.0, point: false },
                Tok::RBracket,
                Tok::Kw(Kw::Goto),
                Tok::Num { value: 10.0, point: false },
            ]
        );
        assert_eq!(toks("G43.4")[1], Tok::Num { value: 43.4, point: true });
        assert_eq!(toks("X.")[1], Tok::Num { value: 0.0, point: true });
        assert_eq!(toks("X1.2.3")[1], Tok::BadNumber);
    }
}
