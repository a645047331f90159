package dev.motionfusion.core.io

/**
 * Malformed input: names the [source] (a file name), the 1-based [line] and the 1-based
 * character [column] where the problem starts (0 when it concerns the whole line or file).
 * The message reads like a compiler's: `file:line:column: what is wrong`.
 */
public class DataFormatException(
    public val source: String,
    public val line: Long,
    public val column: Int,
    public val reason: String,
    cause: Throwable? = null,
) : RuntimeException("$source:$line:$column: $reason", cause)
