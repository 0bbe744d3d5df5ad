set(HARD_ALLOWED unstable)
