"""The conflict locator (thesis Thm 5.2.2): the exact circle locator of §3.1 (Apollonius circles
in quadratic towers), the conic locator of ch. 5, and batch evaluation of independent calls."""
