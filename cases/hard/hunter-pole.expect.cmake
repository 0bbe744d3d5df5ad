set(HARD_ALLOWED completed failed)
