"""The exact engine: regression rows and their hyperplanes, decay rates (the M matrix of
Sui, You and Fu, "Stability of Kalman filtering with multiple sensors involving lossy
communications", Theorem 9), the screens that find the heaviest hyperplanes, verdicts and
critical values, recovery rates, regions, the second-order closed form and the independent
oracle. Every algorithm is chosen from a loss model's capabilities, never from its type.
"""
