/*
 * A table of orientations over time: `t_s,qw,qx,qy,qz[,movement]` (columns found by name, others
 * ignored, gzip detected by its magic bytes). Both the output of `fusion replay` and BROAD's
 * truth.csv.gz are such tables. Quaternions sensor → world, Hamilton, scalar first; an empty,
 * NaN or all-zero quaternion means "unknown" (occluded markers, no orientation yet). movement 1
 * marks scored samples.
 */
package dev.motionfusion.core.input

import dev.motionfusion.core.io.ByteCsvReader
import dev.motionfusion.core.io.CompressionGuard
import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.io.FieldError
import dev.motionfusion.core.io.InputLimits
import dev.motionfusion.core.io.Inputs
import java.io.Closeable
import java.nio.file.Path

/**
 * A cursor over an orientation table: call [next] and, while it returns true, read [timeS], [q]
 * (reused) and [scored]. Streams: memory does not grow with the table.
 */
public class QuaternionTableReader private constructor(private val csv: ByteCsvReader) : Closeable {
    private val cols: IntArray
    private val movement: Int
    private val names: List<String>

    /** True when the table has a movement column. */
    public val hasMovement: Boolean get() = movement >= 0

    /** Time of the current row, s. */
    public var timeS: Double = Double.NaN
        private set

    /** The current orientation [w, x, y, z]; NaN when unknown. */
    public val q: DoubleArray = DoubleArray(4)

    /** True when the current row is scored (movement = 1, or there is no movement column). */
    public var scored: Boolean = true
        private set

    init {
        try {
            val header = csv.header("t_s,qw,qx,qy,qz[,movement]")
            names = header.names
            // A session's own stream (its times in ns of the phone's clock) needs the session's start to be put on t_s.
            if ("t_s" !in names && "timestamp_ns" in names) {
                throw DataFormatException(csv.sourceName, 1, 1, "a session's stream (timestamp_ns, the phone's clock), not a table on t_s: give the session itself (fusion eval SESSION, fusion plot SESSION)")
            }
            cols = IntArray(5) { header.require(COLUMNS[it]) }
            movement = names.indexOf("movement")
        } catch (e: Throwable) {
            csv.close()
            throw e
        }
    }

    /** Advances to the next row; false at the end. */
    public fun next(): Boolean {
        if (!csv.nextRecord()) return false
        var field = cols[0]
        try {
            val previous = timeS
            timeS = csv.parseTimeS(field)
            // Every reader of these tables joins them with another by time: rows out of order would match wrongly.
            if (timeS < previous) throw FieldError("${timeS} s is before the row above (${previous} s): the rows must be in time order")
            for (k in 0 until 4) {
                field = cols[k + 1]
                q[k] = csv.parseDouble(field, emptyIsNaN = true)
            }
            // All zero is no rotation at all (some tools write it for "none yet"): unknown, as an empty row is.
            if (q[0] == 0.0 && q[1] == 0.0 && q[2] == 0.0 && q[3] == 0.0) q.fill(Double.NaN)
            field = movement
            scored = movement < 0 || csv.parseDouble(movement, emptyIsNaN = true) == 1.0
        } catch (e: FieldError) {
            throw csv.error(field, "column ${names[field]}: ${e.reason}")
        }
        return true
    }

    override fun close(): Unit = csv.close()

    public companion object {
        private val COLUMNS = listOf("t_s", "qw", "qx", "qy", "qz")

        /**
         * Opens [path] (plain or gzip).
         * @throws DataFormatException naming the file, line and column of malformed content.
         */
        @JvmStatic
        @JvmOverloads
        public fun open(path: Path, limits: InputLimits = InputLimits()): QuaternionTableReader {
            val name = Inputs.shown(path)
            return QuaternionTableReader(ByteCsvReader(Inputs.maybeGunzip(Inputs.openFile(path), name, CompressionGuard(limits)), name))
        }
    }
}
