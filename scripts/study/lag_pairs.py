"""What lag_pairs_1d.py and lag_pairs_2d.py share: the continuous lag's sub-steps and the carry-over
pair fit (alpha = sum AB / sum BB) of firmware/vo/src/tau_estimator.cpp, written apart from it."""
import numpy as np


def substeps(count, period, tau):
    """A continuous lag integrated in `count` sub-steps a period: (the factor each sub-step keeps,
    the mean age at the read of the input a frame holds, weighted by the pixel's response, and the
    variance of that age). One sub-step is the sampled lag: its input is read at once."""
    keep = np.exp(-period / (count * tau))
    ages = np.arange(count) * period / count
    weight = keep ** np.arange(count)
    mean = float((ages * weight).sum() / weight.sum())
    return keep, mean, float((ages ** 2 * weight).sum() / weight.sum() - mean ** 2)


class PairFit:
    """The sums the pairs are fitted from; tau follows from alpha = exp(-period / tau)."""

    def __init__(self, alpha):
        self.alpha, self.sab, self.sbb, self.see = alpha, 0.0, 0.0, 0.0

    def add(self, A, B):
        self.sab += float((A * B).sum())
        self.sbb += float((B * B).sum())
        self.see += float(((A - self.alpha * B) ** 2).sum())

    def tau(self, period):
        fit = self.sab / self.sbb
        return -period / np.log(fit) if 0 < fit < 1 else float("nan")

    def signal_share(self):
        """B^2 / (A - alpha B)^2 at the true alpha: how far the signal stands above the model's error."""
        return self.sbb / self.see

    def report(self, period, tau):
        """The fit's line: tau read, the truth, the signal's share."""
        return (f"tau {self.tau(period) * 1e3:.2f} ms (true {tau * 1e3:.2f}), "
                f"B^2 / (A - alpha B)^2 {self.signal_share():.1f}")
