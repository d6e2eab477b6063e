//! The worst-case stack depth of a firmware ELF, from its call graph.
//!
//! The simavr tests measure a stack high-water mark: the deepest the
//! sessions they ran went. A path they did not run can go deeper, and on
//! the AVR a stack that grows into `.bss` corrupts it without a fault.
//! This check bounds every path instead (the method of avstack.pl and
//! cargo-call-stack, on the linked code):
//!
//! - each function's own frame is read from its code (`walk`): the pushes,
//!   the frame its prologue allocates through Y (`in r28, SPL` … `sbiw` or
//!   `subi`/`sbci` … `out SPL, r28`), `rcall .+0` allocations, and the depth
//!   at each `call`/`rcall` (+3 bytes: the ATmega2560's 22-bit return
//!   address) and each tail `jmp`/`rjmp` out of the function;
//! - indirect calls (`icall`/`eicall`, and `ijmp`/`eijmp` out of a
//!   function) go to a function whose address the program forms somewhere:
//!   every such address is a code-pointer relocation that
//!   `-Wl,--emit-relocs` keeps (`code_pointers` reads them: vtables and
//!   tables in data, `ldi` pairs of `gs()`). A site whose Z comes from an
//!   `ldi` pair that no relocation formed is a constant address: refused,
//!   with the site named; so is every indirect site of an ELF without such
//!   relocations;
//! - recursion has no bound: a cycle in the call graph is refused and
//!   named;
//! - the thread starts at `main`, which avr-libc's start-up code enters
//!   with a `call` (3 bytes); interrupts come on top: every handler in the
//!   vector table costs its return address (3 bytes) plus its depth. A
//!   handler (or what it calls) that re-enables interrupts (`sei`) can be
//!   interrupted in turn: the worst nesting is every re-enabling handler at
//!   once (none re-entered by its own interrupt) plus the deepest other
//!   one; without `sei` only one handler runs at a time.
//!
//! Each function is walked along its control flow from its entry (`walk`;
//! a call into the middle of a routine is an entry of its own), and where
//! the walk's model does not fit the code (SP set from an unknown Y, paths
//! meeting at different depths, a return with bytes still pushed) it says
//! so in `Bound::odd` rather than guessing quietly. What it assumes: code
//! pointers are formed only through relocations (no address computed from
//! an integer except the `ldi` constants it refuses), and Z at an indirect
//! site built by the two instructions before it is that site's one target.

mod walk;

use std::collections::{BTreeMap, BTreeSet};

use object::{Object, ObjectSection, ObjectSymbol, SymbolKind};

pub use walk::{Leave, Site, Walk};

use super::code_pointers::{self, Kind};
use super::{Image, DATA_SPACE};

/// Bytes a `call` pushes on the ATmega2560 (a 22-bit program counter).
pub const RETURN_ADDRESS: u32 = 3;

/// Interrupt vectors of the ATmega2560 (reset included), 4 bytes each.
pub const VECTORS: u64 = 57;

/// A Rust symbol's path without its hash (`touch_arm::ui::draw::<..>`);
/// other names as they are.
pub fn demangled(name: &str) -> String {
    match rustc_demangle::try_demangle(name) {
        Ok(d) => format!("{d:#}"),
        Err(_) => name.to_string(),
    }
}

/// A function allowed to call itself a known number of levels deep, and
/// why that number holds (the check cannot see it).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Recursion {
    /// The function's demangled path; every instance of it matches
    /// (`…::acc_scan` matches `…::acc_scan::<f32>`).
    pub function: &'static str,
    /// How many times a call of it may call itself again, nested.
    pub levels: u32,
    /// Why that depth holds, for the reader of the check.
    pub why: &'static str,
}

/// The firmware's bounded recursion, each with the reason its depth holds.
pub const FIRMWARE_RECURSION: &[Recursion] = &[Recursion {
    function: "touch_arm::motion::planner::peak_rate::acc_scan",
    levels: 1,
    why: "acc_scan calls itself only when its `refine_first` is true, and passes false",
}];

/// A piece of code the graph walks: a function, or a second entry into one
/// (a call into the middle of a libgcc routine).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Node {
    /// The symbol's name, `name+0x..` for an entry inside it.
    pub name: String,
    /// Byte address of its entry.
    pub start: u64,
    /// One past its last byte (the next symbol, or its section's end).
    pub end: u64,
    /// Its own frame and its calls.
    pub walk: Walk,
}

/// One frame of a worst-case chain.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Step {
    /// The function's demangled name.
    pub name: String,
    /// Depth of the stack when this code starts, bytes (its caller's
    /// frames and return addresses).
    pub entered_at: u32,
    /// The code's own frame on the chain (the depth at the call it makes
    /// next, or its deepest point for the last step).
    pub frame: u32,
    /// Where it calls the next step (None for the last).
    pub call_at: Option<u64>,
}

/// A worst-case chain: from an entry to the deepest point under it.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Chain {
    /// Bytes at the deepest point, the entry's own return address included.
    pub depth: u32,
    /// From the entry down, one per function on the chain.
    pub steps: Vec<Step>,
}

impl std::fmt::Display for Chain {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        for s in &self.steps {
            write!(f, "{:>6} B  {} ({} B", s.entered_at, s.name, s.frame)?;
            match s.call_at {
                Some(at) => writeln!(f, ", calls at {at:#x})")?,
                None => writeln!(f, ", its deepest point)")?,
            }
        }
        write!(f, "{:>6} B  deepest", self.depth)
    }
}

/// An interrupt handler of the vector table.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Handler {
    /// The vector's number (1: INT0 … 56 on the ATmega2560).
    pub vector: u64,
    /// Its worst chain, the 3 bytes the interrupt pushes included.
    pub chain: Chain,
    /// Whether it or anything it calls executes `sei`.
    pub reenables: bool,
}

/// The bound and how it is made up.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Bound {
    /// `main` from avr-libc's `call main`, its 3 bytes included.
    pub thread: Chain,
    /// Every handler the vector table names (not `__bad_interrupt`).
    pub handlers: Vec<Handler>,
    /// Bytes the interrupts add at their worst nesting.
    pub interrupts: u32,
    /// The whole bound: `thread.depth + interrupts`.
    pub total: u32,
    /// Number of pieces of code the graph holds.
    pub nodes: usize,
    /// Number of indirect call and jump sites it resolved.
    pub indirect_sites: usize,
    /// Functions the indirect sites may reach (their address is formed).
    pub address_taken: usize,
    /// Where a function's code did not fit the walk's model, by function.
    pub odd: Vec<String>,
}

impl Bound {
    /// The handlers on the worst nesting, deepest first: every re-enabling
    /// one, then the deepest of the others.
    pub fn worst_nesting(&self) -> Vec<&Handler> {
        let mut on: Vec<&Handler> = self.handlers.iter().filter(|h| h.reenables).collect();
        if let Some(last) = self.handlers.iter().filter(|h| !h.reenables).max_by_key(|h| h.chain.depth) {
            on.push(last);
        }
        on.sort_by_key(|h| std::cmp::Reverse(h.chain.depth));
        on
    }
}

impl std::fmt::Display for Bound {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        writeln!(f, "stack bound {} B: thread {} B + interrupts {} B", self.total, self.thread.depth, self.interrupts)?;
        writeln!(f, "thread:\n{}", self.thread)?;
        for h in self.worst_nesting() {
            let how = if h.reenables { "re-enables interrupts" } else { "interrupts disabled" };
            writeln!(f, "vector {} ({how}):\n{}", h.vector, h.chain)?;
        }
        Ok(())
    }
}

/// The code of the image and what the analysis learns about it.
struct Graph<'i, 'a> {
    image: &'i Image<'a>,
    /// Every code symbol, (start, end, name), in address order.
    code: Vec<(u64, u64, String)>,
    nodes: BTreeMap<u64, Node>,
    /// Functions reachable through a code pointer.
    address_taken: BTreeSet<u64>,
    /// Flash addresses of the `ldi` words a code-pointer relocation wrote.
    ldi_sites: BTreeMap<u64, u64>,
    /// Whether the image kept its relocations at all.
    relocations: bool,
    refusals: Vec<String>,
    indirect_sites: usize,
    allowed: Vec<Recursion>,
    /// Nodes that call themselves as allowed: (levels, the self-call site,
    /// the deepest path without the self-calls).
    recursive: BTreeMap<u64, (u32, u64, Best)>,
}

/// A node's deepest path: bytes below its entry, and the site and target
/// it goes through with the return address that site pushes.
type Best = (u32, Option<(u64, u64, u32)>);

/// Computes the bound, or says why there is none: recursion (the cycle
/// named), an unresolvable indirect call (its site named), a call into no
/// known code.
/// `allowed` lists the functions that may call themselves, and how deep.
pub fn bound(image: &Image, allowed: &[Recursion]) -> Result<Bound, Vec<String>> {
    let mut g = Graph::new(image);
    g.allowed = allowed.to_vec();
    let bad = image.symbol("__bad_interrupt");
    let main = image.symbol("main").ok_or_else(|| vec!["no `main` symbol".to_string()])?;
    let mut memo = BTreeMap::new();
    let thread = g.chain(main, RETURN_ADDRESS, &mut memo, &mut Vec::new());
    let mut handlers = Vec::new();
    for vector in 1..VECTORS {
        let Some(words) = image.bytes(4 * vector, 4) else { break };
        let words = super::avr_insn::words(words);
        // `jmp handler`, or `rjmp handler; nop` once `--relax` shortened it.
        let target = match walk::decode(&words).0 {
            walk::Op::Plain(super::avr_insn::Insn::Jmp(t)) => u64::from(t),
            walk::Op::Rjmp(k) => (4 * vector + 2).wrapping_add_signed(i64::from(k)),
            _ => {
                g.refusals.push(format!("vector {vector} at {:#x} is neither a `jmp` nor an `rjmp`", 4 * vector));
                continue;
            }
        };
        if Some(target) == bad {
            continue;
        }
        let chain = g.chain(target, RETURN_ADDRESS, &mut memo, &mut Vec::new());
        let reenables = g.reaches_sei(target);
        handlers.push(Handler { vector, chain, reenables });
    }
    if !g.refusals.is_empty() {
        let mut r = g.refusals;
        r.sort();
        r.dedup();
        return Err(r);
    }
    let mut b = Bound {
        thread,
        handlers,
        interrupts: 0,
        total: 0,
        nodes: g.nodes.len(),
        indirect_sites: g.indirect_sites,
        address_taken: g.address_taken.len(),
        odd: g.nodes.values().flat_map(|n| n.walk.odd.iter().map(move |o| format!("{}: {o}", n.name))).collect(),
    };
    b.interrupts = b.worst_nesting().iter().map(|h| h.chain.depth).sum();
    b.total = b.thread.depth + b.interrupts;
    Ok(b)
}

/// [`bound`] with the firmware's [`FIRMWARE_RECURSION`], failing when it
/// exceeds `budget` bytes (the ELF's `firmware::stack_budget`: memory.x's
/// `__budget_stack`, or the bench's free RAM less a margin): the error
/// prints the worst chain.
pub fn check(image: &Image, budget: u64) -> Result<Bound, String> {
    let b = bound(image, FIRMWARE_RECURSION).map_err(|r| r.join("\n"))?;
    if u64::from(b.total) > budget {
        return Err(format!("the stack bound exceeds the {budget}-byte stack budget\n{b}"));
    }
    Ok(b)
}

/// The deepest path under one node, memoized as (depth below the node's
/// entry, the site and target it goes through).
type Memo = BTreeMap<u64, Option<Best>>;

impl<'i, 'a> Graph<'i, 'a> {
    fn new(image: &'i Image<'a>) -> Graph<'i, 'a> {
        // Every named symbol in a code section of flash, typed or not:
        // avr-libc's and libgcc's assembly routines often carry no `.type`.
        let code_sections: BTreeMap<usize, u64> = image
            .file
            .sections()
            .filter(|s| s.kind() == object::SectionKind::Text && s.address() < DATA_SPACE)
            .map(|s| (s.index().0, s.address() + s.size()))
            .collect();
        let mut starts: Vec<(u64, u64, bool, String)> = image
            .file
            .symbols()
            .filter(|s| matches!(s.kind(), SymbolKind::Text | SymbolKind::Unknown))
            .filter_map(|s| {
                let end = *code_sections.get(&s.section_index()?.0)?;
                Some((s.address(), end, s.kind() == SymbolKind::Text, s.name().ok()?.to_string()))
            })
            .filter(|(_, _, _, name)| !name.is_empty() && !name.starts_with('.'))
            .collect();
        // A function wins over an untyped label at its address.
        starts.sort_by_key(|(at, _, typed, _)| (*at, std::cmp::Reverse(*typed)));
        starts.dedup_by_key(|(at, _, _, _)| *at);
        // Each piece of code runs to the next symbol: calls land on local
        // labels past a routine's `.size` too.
        let code = starts
            .iter()
            .enumerate()
            .map(|(i, (at, section_end, _, name))| {
                let next = starts.get(i + 1).map_or(*section_end, |n| n.0);
                (*at, next.min(*section_end), demangled(name))
            })
            .collect();
        let pointers = code_pointers::check(image);
        let address_taken = pointers
            .sites
            .iter()
            .filter(|s| s.kind != Kind::Hh8Pm && s.target < DATA_SPACE)
            .map(|s| s.target)
            .collect();
        let ldi_sites = pointers.sites.iter().filter(|s| s.kind != Kind::Pm16).map(|s| (s.at, s.target)).collect();
        let relocations = image.file.sections().any(|s| s.relocations().next().is_some());
        Graph {
            image,
            code,
            nodes: BTreeMap::new(),
            address_taken,
            ldi_sites,
            relocations,
            refusals: Vec::new(),
            indirect_sites: 0,
            allowed: Vec::new(),
            recursive: BTreeMap::new(),
        }
    }

    /// The node starting at `at`, walked on first use.
    fn node(&mut self, at: u64) -> Option<&Node> {
        if !self.nodes.contains_key(&at) {
            let i = self.code.partition_point(|c| c.0 <= at).checked_sub(1)?;
            let (start, end, name) = self.code[i].clone();
            if at >= end {
                return None;
            }
            let name = if at == start { name } else { format!("{name}+{:#x}", at - start) };
            let bytes = self.image.bytes(at, end - at)?;
            let walk = walk::walk(at, bytes, |t| (start..end).contains(&t));
            self.nodes.insert(at, Node { name, start: at, end, walk });
        }
        self.nodes.get(&at)
    }

    fn name(&self, at: u64) -> String {
        self.nodes.get(&at).map_or_else(|| format!("{at:#x}"), |n| n.name.clone())
    }

    /// Where an indirect site at `at` in `node` may go.
    fn indirect_targets(&mut self, node: u64, at: u64) -> Vec<u64> {
        self.indirect_sites += 1;
        let site = format!("{} at {at:#x}", self.name(node));
        if !self.relocations {
            self.refusals.push(format!("{site}: an indirect call, and the ELF has no relocations to resolve it from (link with -Wl,--emit-relocs)"));
            return Vec::new();
        }
        // Z loaded by the two instructions before the site.
        let before = |back: u64| self.image.bytes(at.wrapping_sub(back), 2).map(|b| u16::from_le_bytes([b[0], b[1]]));
        let ldi_z = |w: Option<u16>| {
            matches!(
                w.map(|w| super::avr_insn::Insn::decode(&[w]).0),
                Some(super::avr_insn::Insn::Ldi { d: 30 | 31, .. })
            )
        };
        if at >= node + 4 && ldi_z(before(2)) && ldi_z(before(4)) {
            return match (self.ldi_sites.get(&(at - 2)), self.ldi_sites.get(&(at - 4))) {
                (Some(&a), Some(&b)) if a == b => vec![a],
                _ => {
                    self.refusals.push(format!(
                        "{site}: an indirect call through a constant Z that no code-pointer relocation formed (a cast integer?)"
                    ));
                    Vec::new()
                }
            };
        }
        if self.address_taken.is_empty() {
            self.refusals.push(format!("{site}: an indirect call, and the image forms no code pointer it could go to"));
        }
        self.address_taken.iter().copied().collect()
    }

    /// The worst chain from `at`, entered `entry` bytes deep (its return
    /// address).
    fn chain(&mut self, at: u64, entry: u32, memo: &mut Memo, path: &mut Vec<u64>) -> Chain {
        let Some(below) = self.depth(at, memo, path) else { return Chain::default() };
        let mut chain = Chain { depth: entry + below, steps: Vec::new() };
        let (mut here, mut entered) = (at, entry);
        while chain.steps.len() < 10_000 {
            let Some(Some((_, mut via))) = memo.get(&here).copied() else { break };
            if let Some(&(levels, site, without)) = self.recursive.get(&here) {
                // The allowed self-calls, then the deepest path of the last level.
                let step = self.site_depth(here, site) + RETURN_ADDRESS;
                for _ in 0..levels {
                    let frame = self.site_depth(here, site);
                    chain.steps.push(Step { name: self.name(here), entered_at: entered, frame, call_at: Some(site) });
                    entered += step;
                }
                via = without.1;
            }
            let own = self.nodes.get(&here).map_or(0, |n| n.walk.own);
            match via {
                Some((site, next, push)) => {
                    let depth_at = self.site_depth(here, site);
                    chain.steps.push(Step {
                        name: self.name(here),
                        entered_at: entered,
                        frame: depth_at,
                        call_at: Some(site),
                    });
                    entered += depth_at + push;
                    here = next;
                }
                None => {
                    chain.steps.push(Step { name: self.name(here), entered_at: entered, frame: own, call_at: None });
                    break;
                }
            }
        }
        chain
    }

    fn site_depth(&self, node: u64, site: u64) -> u32 {
        self.nodes.get(&node).and_then(|n| n.walk.sites.iter().find(|s| s.at == site)).map_or(0, |s| s.depth)
    }

    /// Bytes below `at`'s entry on its deepest path (its own return
    /// address not counted), or None when that cannot be bounded (the
    /// reason is in `refusals`).
    fn depth(&mut self, at: u64, memo: &mut Memo, path: &mut Vec<u64>) -> Option<u32> {
        if let Some(done) = memo.get(&at) {
            return done.map(|d| d.0);
        }
        if let Some(i) = path.iter().position(|&p| p == at) {
            let mut cycle: Vec<String> = path[i..].iter().map(|&p| self.name(p)).collect();
            cycle.push(self.name(at));
            self.refusals.push(format!("recursion: {}", cycle.join(" -> ")));
            return None;
        }
        let Some(node) = self.node(at) else {
            self.refusals.push(format!("a call to {at:#x}, where no code symbol is"));
            memo.insert(at, None);
            return None;
        };
        let (own, sites, name) = (node.walk.own, node.walk.sites.clone(), node.name.clone());
        let levels = self.allowed.iter().find(|r| name.starts_with(r.function)).map(|r| r.levels);
        path.push(at);
        let mut best: Best = (own, None);
        let mut bounded = true;
        let mut itself: Vec<(u64, u32)> = Vec::new();
        for site in sites {
            let (targets, push) = match site.leave {
                Leave::Call(t) => (vec![t], RETURN_ADDRESS),
                Leave::Jump(t) => (vec![t], 0),
                Leave::IndirectCall => (self.indirect_targets(at, site.at), RETURN_ADDRESS),
                Leave::IndirectJump => (self.indirect_targets(at, site.at), 0),
            };
            for t in targets {
                if t == at && levels.is_some() {
                    itself.push((site.at, site.depth + push));
                    continue;
                }
                match self.depth(t, memo, path) {
                    Some(d) => {
                        let total = site.depth + push + d;
                        if total > best.0 {
                            best = (total, Some((site.at, t, push)));
                        }
                    }
                    None => bounded = false,
                }
            }
        }
        // Allowed self-calls: each level adds the deepest self-call site's
        // depth to what the level below it reaches.
        if let (Some(levels), Some(&(site, step))) = (levels, itself.iter().max_by_key(|s| s.1)) {
            self.recursive.insert(at, (levels, site, best));
            best = (best.0.max(step * levels + best.0), Some((site, at, step)));
        }
        path.pop();
        let result = bounded.then_some(best);
        // Unbounded is remembered too: a later path through this node is
        // refused without naming its cycle again.
        memo.insert(at, result);
        result.map(|r| r.0)
    }

    /// Whether `sei` runs in `at` or anything it reaches (walked nodes).
    fn reaches_sei(&mut self, at: u64) -> bool {
        let mut seen = BTreeSet::new();
        let mut todo = vec![at];
        while let Some(n) = todo.pop() {
            if !seen.insert(n) {
                continue;
            }
            let Some(node) = self.node(n) else { continue };
            if node.walk.sei {
                return true;
            }
            for s in node.walk.sites.clone() {
                match s.leave {
                    Leave::Call(t) | Leave::Jump(t) => todo.push(t),
                    Leave::IndirectCall | Leave::IndirectJump => todo.extend(self.address_taken.iter().copied()),
                }
            }
        }
        false
    }
}

/// The functions the indirect sites may reach: every code-pointer
/// relocation's target, as `code_pointers` reads them, by name.
pub fn address_taken(image: &Image) -> Vec<(String, u64)> {
    let g = Graph::new(image);
    let mut out: Vec<(String, u64)> = g
        .address_taken
        .iter()
        .map(|&t| {
            let i = g.code.partition_point(|c| c.0 <= t).saturating_sub(1);
            let name = g.code.get(i).filter(|c| c.0 == t).map_or_else(|| format!("{t:#x}"), |c| c.2.clone());
            (name, t)
        })
        .collect();
    out.sort();
    out
}
