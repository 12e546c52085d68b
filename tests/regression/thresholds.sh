# Sourced by check.sh: the `foldcast diff` thresholds of the visual regression suite, chosen
# from measured noise (docs/compare.md, "Visual regression suite"): run to run, thread count
# and Release vs the sanitizer build give identical pixels; forcing Embree's SSE4.2/AVX
# kernels (another CPU) changed 1 pixel of 12288 by at most 6/255.  A pixel fails above 5/255
# (0.02); FAILURE when more than 0.5 % of the pixels fail (61 at 128x96: 60x the measured
# share) or any channel moves by more than 0.5 (a small object gone or added: 20x the
# measured 0.0235).  Pixels moving by more than 1/255 warn; more than 0.1 % of them is a
# WARNING (the test passes, the pictures are kept in regression-artifacts/ for a look).
DIFF_THRESHOLDS=(--fail 0.02 --failpercent 0.5 --hardfail 0.5 --warn 0.004 --warnpercent 0.1)
