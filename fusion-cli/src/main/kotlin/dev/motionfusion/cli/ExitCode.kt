package dev.motionfusion.cli

/** Exit codes of the `fusion` command, documented in `fusion --help`. */
internal object ExitCode {
    /** Success. */
    const val OK = 0

    /** The input was read but is malformed (the message names file, line and column). */
    const val DATA_ERROR = 1

    /** Wrong command line (unknown subcommand or option, missing argument). */
    const val USAGE = 2

    /** A file or standard output could not be read or written (missing, unreadable, disk full), or out of memory. */
    const val IO_ERROR = 3

    /** `fusion listen`: the connection to the phone was lost (no close from it, or no answer to pings). */
    const val CONNECTION_LOST = 4

    /** `fusion listen`: the phone's user denied this laptop, or did not answer in time. */
    const val DENIED = 5

    /** A bug of fusion: an unexpected exception, reported in one line instead of a stack trace. */
    const val INTERNAL_ERROR = 70
}
