package dev.motionfusion.cli

/** A wrong command line; the message says what to change. */
internal class UsageException(message: String) : RuntimeException(message)
