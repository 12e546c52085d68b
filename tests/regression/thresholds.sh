# Sourced by check.sh: the `foldcast diff` thresholds of the visual regression suite, chosen
# from measured noise (docs/compare.md, "Visual regression suite": the figures and the margin).
DIFF_THRESHOLDS=(--fail 0.02 --failpercent 0.5 --hardfail 0.5 --warn 0.004 --warnpercent 0.1)
