//! A small Markdown page builder.

#[derive(Default)]
pub struct Page {
    text: String,
}

impl Page {
    pub fn new(title: &str) -> Page {
        Page {
            text: format!("# {title}\n\n"),
        }
    }

    pub fn empty() -> Page {
        Page {
            text: String::new(),
        }
    }

    pub fn h2(&mut self, t: &str) {
        self.text += &format!("## {t}\n\n");
    }

    pub fn h3(&mut self, t: &str) {
        self.text += &format!("### {t}\n\n");
    }

    pub fn para(&mut self, t: &str) {
        self.text += &format!("{t}\n\n");
    }

    pub fn bullets(&mut self, items: &[String]) {
        for i in items {
            self.text += &format!("- {i}\n");
        }
        self.text += "\n";
    }

    pub fn table(&mut self, header: &[&str], rows: &[Vec<String>]) {
        self.text += &format!("| {} |\n", header.join(" | "));
        self.text += &format!("|{}\n", "---|".repeat(header.len()));
        for r in rows {
            self.text += &format!("| {} |\n", r.join(" | "));
        }
        self.text += "\n";
    }

    pub fn image(&mut self, alt: &str, file: &str) {
        self.text += &format!("![{alt}]({file})\n\n");
    }

    pub fn code(&mut self, t: &str) {
        self.text += &format!("```text\n{t}\n```\n\n");
    }

    /// Appends Markdown text as it is (e.g. a peer script's results).
    pub fn append_raw(&mut self, text: &str) {
        self.text += text;
        if !text.ends_with("\n\n") {
            self.text += "\n";
        }
    }

    pub fn append(&mut self, other: Page) {
        self.text += &other.text;
    }

    pub fn finish(self) -> String {
        self.text
    }
}

/// `1.23e-4` style for errors, plain for moderate numbers.
pub fn sci(x: f64) -> String {
    if !x.is_finite() {
        return format!("{x}");
    }
    if x == 0.0 {
        return "0".into();
    }
    if x.abs() < 1e-2 || x.abs() >= 1e5 {
        format!("{x:.2e}")
    } else {
        format!("{x:.3}")
    }
}

/// One row of the report's headline table: a claim, our figure, the peer's or
/// reference's, their ratio, and where the figures come from.
#[derive(Clone, Debug)]
pub struct Headline {
    pub claim: String,
    pub ours: String,
    pub peer: String,
    pub ratio: String,
    pub basis: String,
}

thread_local! {
    /// The headlines of the report this thread writes (a report runs on one thread; the
    /// tests write two at once).
    static HEADLINES: std::cell::RefCell<Vec<Headline>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// Adds a row to the headline table (sections call this where they measure a claim).
pub fn headline(
    claim: impl Into<String>,
    ours: impl Into<String>,
    peer: impl Into<String>,
    ratio: impl Into<String>,
    basis: impl Into<String>,
) {
    let row = Headline {
        claim: claim.into(),
        ours: ours.into(),
        peer: peer.into(),
        ratio: ratio.into(),
        basis: basis.into(),
    };
    HEADLINES.with(|h| h.borrow_mut().push(row));
}

/// The headline rows recorded so far, in the order the sections ran.
/// Forgets the headlines so far (a section run only for what it writes to disk).
pub fn clear_headlines() {
    HEADLINES.with(|h| h.borrow_mut().clear());
}

pub fn headlines() -> Vec<Headline> {
    HEADLINES.with(|h| h.borrow().clone())
}
