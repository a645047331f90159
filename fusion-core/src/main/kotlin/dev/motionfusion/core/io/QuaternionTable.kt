/*
 * A table of orientations over time: `t_s,qw,qx,qy,qz[,movement]` (columns found by name, others
 * ignored, gzip detected by its magic bytes). Both the output of `fusion replay` and BROAD's
 * truth.csv.gz are such tables. Quaternions sensor → world, Hamilton, scalar first; an empty
 * or NaN quaternion means "unknown" (occluded markers). movement 1 marks scored samples.
 */
package dev.motionfusion.core.io

import java.nio.file.Files
import java.nio.file.Path

/** Orientations in memory: [timeS] s, [q] rows [w, x, y, z], [scored] (all true without a movement column). */
public class QuaternionTable(
    public val name: String,
    public val timeS: DoubleArray,
    public val q: Array<DoubleArray>,
    public val scored: BooleanArray,
    public val hasMovement: Boolean,
) {
    public val size: Int get() = timeS.size

    public companion object {
        /**
         * Reads [path].
         * @throws DataFormatException naming the file, line and column of malformed content.
         */
        @JvmStatic
        public fun read(path: Path): QuaternionTable {
            val name = path.toString()
            ByteCsvReader(Inputs.maybeGunzip(Files.newInputStream(path)), name).use { csv ->
                if (!csv.nextLine()) throw DataFormatException(name, 1, 0, "empty file: expected a header t_s,qw,qx,qy,qz")
                val names = (0 until csv.count).map { csv.text(it).trim().removePrefix("\uFEFF").removeSurrounding("\"") }
                val cols = listOf("t_s", "qw", "qx", "qy", "qz").map { c ->
                    names.indexOf(c).also { if (it < 0) throw DataFormatException(name, csv.lineNumber, 1, "header lacks column '$c'; expected t_s,qw,qx,qy,qz[,movement]") }
                }
                val mv = names.indexOf("movement")
                val need = maxOf(cols.max(), mv) + 1
                var t = DoubleArray(1024)
                var qs = ArrayList<DoubleArray>()
                var scored = BooleanArray(1024)
                var n = 0
                while (csv.nextLine()) {
                    if (csv.count < need) throw csv.error(csv.count, "row has ${csv.count} fields, expected $need")
                    if (n == t.size) {
                        t = t.copyOf(n * 2)
                        scored = scored.copyOf(n * 2)
                    }
                    var field = cols[0]
                    try {
                        t[n] = csv.parseDouble(field)
                        val row = DoubleArray(4)
                        for (k in 0 until 4) {
                            field = cols[k + 1]
                            row[k] = csv.parseDouble(field, emptyIsNaN = true)
                        }
                        qs.add(row)
                        field = mv
                        scored[n] = mv < 0 || csv.parseDouble(mv, emptyIsNaN = true) == 1.0
                    } catch (e: FieldError) {
                        throw csv.error(field, "column ${names[field]}: ${e.reason}")
                    }
                    n++
                }
                return QuaternionTable(name, t.copyOf(n), qs.toTypedArray(), scored.copyOf(n), mv >= 0)
            }
        }
    }
}
