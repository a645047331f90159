package dev.motionfusion.core.io

/**
 * Malformed input: names the [source] (a file name), the 1-based [line] and the 1-based
 * character [column] where the problem starts (0 when it concerns the whole line or file).
 * The message reads like a compiler's: `file:line:column: what is wrong`; a 0 is left out
 * (`file:line: …`, `file: …`), so no message shows a position that does not exist.
 */
public class DataFormatException(
    public val source: String,
    public val line: Long,
    public val column: Int,
    public val reason: String,
    cause: Throwable? = null,
) : RuntimeException(location(source, line, column) + reason, cause) {
    private companion object {
        /** `file:line:column: `, `file:line: ` or `file: ` (no 0 where nothing is known). */
        fun location(source: String, line: Long, column: Int): String = when {
            line <= 0 -> "$source: "
            column <= 0 -> "$source:$line: "
            else -> "$source:$line:$column: "
        }
    }
}
