"""Trial order and participant lists, bit for bit as the experiment page computes them.

The page (``static/task.js``) shuffles the trials of each participant with a
small seeded generator so that the order is random across participants but
reproducible: the same participant id (and study seed) always gives the same
order, in the browser, in the PsychoPy script and here. Both sides use

* FNV-1a (32 bit) over the UTF-8 bytes of ``seed + ":" + participant`` as the
  seed (Fowler, Noll & Vo; the IETF draft cited below),
* mulberry32 (Tommy Ettinger's 32-bit generator, public domain), giving
  floats ``u / 2**32`` that are exact in IEEE doubles on both sides,
* the Fisher-Yates shuffle drawing ``j = floor(r * (i + 1))`` for
  ``i = n-1 .. 1`` (Durstenfeld 1964; Knuth, TAOCP vol. 2, Algorithm P).

Every operation is on 32-bit unsigned integers or exactly representable
doubles, so the Python and JavaScript sequences are identical (a test runs
both).

Counterbalancing assigns stimuli to ``K`` participant lists by a Latin
square over conditions: stimuli that share an item (the same ``parent_id``,
e.g. the peak and trough fragments of one base shape) go to different lists,
and each list sees each condition equally often across items.

References
----------
.. [1] Fowler, G., Noll, L. C., Vo, K.-P., Eastlake, D. & Hansen, T. (2019).
       The FNV non-cryptographic hash algorithm. IETF draft-eastlake-fnv-17.
.. [2] Durstenfeld, R. (1964). Algorithm 235: Random permutation.
       Communications of the ACM, 7(7), 420.
.. [3] Knuth, D. E. (1997). The Art of Computer Programming, vol. 2:
       Seminumerical Algorithms (3rd ed.), section 3.4.2.
.. [4] Ettinger, T. (2017). mulberry32. Public-domain 32-bit PRNG, as
       collected in https://github.com/bryc/code/blob/master/jshash/PRNGs.md
.. [5] Pollatsek, A. & Well, A. D. (1995). On the use of counterbalanced
       designs in cognitive research. Journal of Experimental Psychology:
       Learning, Memory, and Cognition, 21(3), 785-794.
"""

from __future__ import annotations

from attneave.stimuli.errors import InputError

__all__ = ["fnv1a32", "mulberry32", "shuffle", "trial_order", "participant_list", "latin_square_lists"]

_M32 = 0xFFFFFFFF


def fnv1a32(text):
    """FNV-1a 32-bit hash of the UTF-8 bytes of `text`.

    Parameters
    ----------
    text : str

    Returns
    -------
    int
        In ``[0, 2**32)``.

    Examples
    --------
    >>> fnv1a32("")          # the FNV offset basis
    2166136261
    >>> hex(fnv1a32("a"))    # test vector of the FNV reference
    '0xe40c292c'
    """
    h = 0x811C9DC5
    for byte in str(text).encode("utf-8"):
        h ^= byte
        h = (h * 0x01000193) & _M32
    return h


def mulberry32(seed):
    """A generator of floats in [0, 1): mulberry32 seeded with a 32-bit integer.

    Parameters
    ----------
    seed : int
        Taken modulo ``2**32``.

    Returns
    -------
    callable
        Each call returns the next float ``u / 2**32`` with ``u`` a 32-bit
        unsigned integer; the JavaScript ``mulberry32`` of ``task.js``
        returns the same sequence.

    Examples
    --------
    >>> r = mulberry32(1)
    >>> [round(r(), 6) for _ in range(3)]
    [0.627074, 0.002736, 0.527447]
    """
    state = [seed & _M32]

    def imul(a, b):
        # JavaScript Math.imul: the low 32 bits of the product
        return (a * b) & _M32

    def draw():
        a = state[0] = (state[0] + 0x6D2B79F5) & _M32
        t = imul(a ^ (a >> 15), 1 | a)
        t = ((t + imul(t ^ (t >> 7), 61 | t)) & _M32) ^ t
        return ((t ^ (t >> 14)) & _M32) / 4294967296.0

    return draw


def shuffle(items, rng):
    """Fisher-Yates shuffle of a copy of `items`, drawing from `rng`.

    Parameters
    ----------
    items : sequence
    rng : callable
        Returns floats in [0, 1), e.g. from :func:`mulberry32`.

    Returns
    -------
    list
        A permutation of `items`; `items` is not changed.
    """
    out = list(items)
    for i in range(len(out) - 1, 0, -1):
        j = int(rng() * (i + 1))  # floor: the product is non-negative
        out[i], out[j] = out[j], out[i]
    return out


def _rng_for(participant, seed, purpose=""):
    return mulberry32(fnv1a32(f"{purpose}{seed}:{participant}"))


def trial_order(participant, stimulus_ids, conditions=None, order="random", seed=""):
    """The order in which one participant sees the main trials.

    Parameters
    ----------
    participant : str
        Participant id as entered (``?participant=`` of the page).
    stimulus_ids : sequence of str
        The participant's stimuli (their list, practice removed) in manifest order.
    conditions : sequence of str, optional
        Condition of each stimulus; needed for ``order='blocked'``.
    order : {'random', 'blocked', 'fixed'}
        ``random``: one shuffle of all trials. ``blocked``: the conditions in
        a shuffled order (in order of first appearance before shuffling),
        the trials of each block shuffled, one generator for all draws.
        ``fixed``: manifest order.
    seed : str
        Study seed; a new seed gives every participant a new order.

    Returns
    -------
    list of str
        Stimulus ids in presentation order.

    Examples
    --------
    >>> trial_order("P01", ["a", "b", "c", "d"]) == trial_order("P01", ["a", "b", "c", "d"])
    True
    """
    ids = list(stimulus_ids)
    if order == "fixed":
        return ids
    rng = _rng_for(participant, seed)
    if order == "random":
        return shuffle(ids, rng)
    if order != "blocked":
        raise ValueError(f"order must be 'random', 'blocked' or 'fixed', got {order!r}")
    if conditions is None or len(conditions) != len(ids):
        raise ValueError("order='blocked' needs one condition per stimulus")
    blocks = list(dict.fromkeys(conditions))
    out = []
    for block in shuffle(blocks, rng):
        out += shuffle([s for s, c in zip(ids, conditions) if c == block], rng)
    return out


def participant_list(participant, n_lists, seed=""):
    """The list (1..`n_lists`) of a participant who was not given ``?list=``.

    Parameters
    ----------
    participant : str
    n_lists : int
    seed : str

    Returns
    -------
    int
        ``fnv1a32("list:" + seed + ":" + participant) mod n_lists + 1``. This
        is balanced only on average; give ``?list=`` for exact balance.
    """
    return fnv1a32(f"list:{seed}:{participant}") % int(n_lists) + 1


def latin_square_lists(stimulus_ids, items, conditions, n_lists):
    """Assign stimuli to participant lists by a Latin square over conditions.

    Stimuli are grouped into items (usually by ``parent_id``: a base shape and
    the stimuli derived from it). An item with one stimulus appears in every
    list. In an item with several stimuli, ordered by the order in which
    their conditions first appear in the set, the stimulus of rank ``r`` goes
    to list ``(r + i) mod K + 1`` where ``i`` is the item's index among the
    multi-stimulus items: the rows of a cyclic Latin square, so the
    conditions of one item land in different lists and, across ``K``
    consecutive items, every list sees every condition once.

    Parameters
    ----------
    stimulus_ids, items, conditions : sequence of str
        One entry per stimulus, in manifest order.
    n_lists : int
        ``K >= 1``.

    Returns
    -------
    dict of str -> list of int
        The lists (1-based) of each stimulus.

    Raises
    ------
    InputError
        An item has more stimuli than there are lists (they cannot all go to
        different lists).

    Examples
    --------
    >>> latin_square_lists(["a1", "b1", "a2", "b2", "f"], ["1", "1", "2", "2", "f"],
    ...                    ["peaks", "troughs", "peaks", "troughs", "filler"], 2)
    {'a1': [1], 'b1': [2], 'a2': [2], 'b2': [1], 'f': [1, 2]}
    """
    K = int(n_lists)
    if K < 1:
        raise ValueError("n_lists must be >= 1")
    rank_of = {c: k for k, c in enumerate(dict.fromkeys(conditions))}
    members = {}
    for sid, item, cond in zip(stimulus_ids, items, conditions):
        members.setdefault(item, []).append((rank_of[cond], sid))
    out = {}
    i = 0
    for item, ms in members.items():
        if len(ms) == 1 or K == 1:
            for _, sid in ms:
                out[sid] = list(range(1, K + 1))
            continue
        if len(ms) > K:
            raise InputError(
                f"--lists {K}: item {item!r} has {len(ms)} stimuli ({', '.join(s for _, s in ms)}), which cannot "
                f"all go to different lists; use at least {len(ms)} lists or select conditions (--conditions)"
            )
        for r, (_, sid) in enumerate(sorted(ms, key=lambda m: m[0])):
            out[sid] = [(r + i) % K + 1]
        i += 1
    return {sid: out[sid] for sid in stimulus_ids}
