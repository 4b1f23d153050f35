"""The comparison workflow's steps (`steps`) and its report (`report`)."""
