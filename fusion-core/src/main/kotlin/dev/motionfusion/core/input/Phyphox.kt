/*
 * phyphox exports (docs/IMPORT.md): one CSV per data set in a zip or folder, or a single CSV.
 * Headers name a time column and one column per axis, in any of the forms phyphox writes:
 *   Android simple experiments  "Time (s)","Gyroscope x (rad/s)",…
 *   iOS simple experiments      "Time (s)","X (rad/s)",…  (the sensor is the file's name)
 *   custom experiments          "time","Gyroscope x",…    (no units: phyphox's SI units)
 * comma, tab or semicolon separated; decimal point, or decimal comma with a non-comma separator.
 * phyphox already writes acceleration in Android's sign on both platforms (iOS multiplies
 * CoreMotion's values by −9.81), so no platform conversion is needed.
 */
package dev.motionfusion.core.input

import dev.motionfusion.core.io.ByteCsvReader
import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.io.FileSet
import dev.motionfusion.core.event.SessionStream

internal object PhyphoxImport {
    /** What a data set measures. Only the first three are filter inputs. */
    private enum class Quantity(val stream: SessionStream?, val units: Map<String, Double>) {
        ACCELERATION(SessionStream.ACCELEROMETER, mapOf("" to 1.0, "m/s^2" to 1.0, "m/s²" to 1.0, "m/s2" to 1.0)),
        GYROSCOPE(SessionStream.GYROSCOPE, mapOf("" to 1.0, "rad/s" to 1.0, "deg/s" to Math.PI / 180, "°/s" to Math.PI / 180)),
        MAGNETIC_FIELD(SessionStream.MAGNETOMETER, mapOf("" to 1.0, "µt" to 1.0, "μt" to 1.0, "ut" to 1.0)),
        LINEAR_ACCELERATION(null, emptyMap()),
        GRAVITY(null, emptyMap()),
    }

    private fun quantity(name: String): Quantity? = when (name.lowercase().replace('_', ' ').trim()) {
        "acceleration", "accel", "accelerometer", "acc" -> Quantity.ACCELERATION
        "gyroscope", "gyro", "rotation rate", "angular velocity" -> Quantity.GYROSCOPE
        "magnetic field", "magnetometer", "mag" -> Quantity.MAGNETIC_FIELD
        "linear acceleration", "linear accelerometer", "linearacceleration" -> Quantity.LINEAR_ACCELERATION
        "gravity" -> Quantity.GRAVITY
        else -> null
    }

    /** A copy's mark after a file's name: "_2", " 2", "-2", "_v3", " (1)". */
    private val COPY = Regex("""(?:[ _-]?v?\d+|\s*\(\d+\))$""", RegexOption.IGNORE_CASE)

    private fun baseName(path: String) = path.substringAfterLast('/').substringBeforeLast('.').replace(Regex("""(?i)^raw data_?"""), "")

    /** The quantity a file is named after ("Accelerometer.csv", "Raw Data_Gyroscope.csv", a copy "Gyroscope_2.csv"), or null. */
    private fun fileQuantity(path: String): Quantity? = baseName(path).let { quantity(it) ?: quantity(it.replace(COPY, "")) }

    /** How well [path]'s name says [q]: 2 named after it, 1 a copy's name ("Gyroscope_2"), 0 not. */
    private fun naming(path: String, q: Quantity): Int = when {
        quantity(baseName(path)) == q -> 2
        fileQuantity(path) == q -> 1
        else -> 0
    }

    private val TIME = Regex("""^time(?: \(s\))?$""", RegexOption.IGNORE_CASE)

    /** "<quantity> x (<unit>)", "x (<unit>)", "<quantity> x", "<quantity>_x (<unit>)". */
    private val AXIS = Regex("""^(?:(.*?)[ _])?([xyz])(?: \(([^)]*)\))?$""", RegexOption.IGNORE_CASE)

    /** The columns of one data set found in a header. */
    private class DataSet(val quantity: Quantity, val columns: IntArray, val units: Array<String>)

    private class Header(val dialect: Dialect, val names: List<String>, val time: Int, val sets: List<DataSet>)

    /** The header of a phyphox CSV named [fileName], or null when it is not one. */
    private fun parse(header: String, fileName: String): Header? {
        val dialect = Dialect.detect(header)
        val names = ByteCsvReader.headerNames(header, dialect.separator)
        val times = names.indices.filter { TIME.matches(names[it]) }
        if (times.size != 1) return null
        val fromFile = fileQuantity(fileName)
        val found = LinkedHashMap<Quantity, Array<MutableList<Pair<Int, String>>>>()
        for ((i, n) in names.withIndex()) {
            val m = AXIS.matchEntire(n) ?: continue
            val q = if (m.groupValues[1].isEmpty()) fromFile else quantity(m.groupValues[1])
            q ?: continue
            val axis = "xyz".indexOf(m.groupValues[2].lowercase()[0])
            found.getOrPut(q) { Array(3) { ArrayList() } }[axis] += i to m.groupValues[3].trim().lowercase()
        }
        val sets = found.mapNotNull { (q, axes) ->
            if (axes.any { it.isEmpty() }) return@mapNotNull null
            if (axes.any { it.size > 1 }) return null // the same axis twice: ambiguous, not read as phyphox
            DataSet(q, IntArray(3) { axes[it][0].first }, Array(3) { axes[it][0].second })
        }
        if (sets.isEmpty()) return null
        return Header(dialect, names, times[0], sets)
    }

    /** True when [header] is a phyphox header of a data set this importer knows. */
    fun recognises(header: String, fileName: String): Boolean = parse(header, fileName) != null

    private fun isCsv(path: String) = path.endsWith(".csv", ignoreCase = true)

    /**
     * The experiment's end from meta/time.csv (the experiment time of the last event, when that is
     * a PAUSE), s; +∞ when not stated. Rows after it come from another recording put beside.
     */
    private fun experimentEnd(files: FileSet, dir: String): Double {
        val path = files.find(dir, "meta/time.csv") ?: return Double.POSITIVE_INFINITY
        val header = files.firstLine(path) ?: return Double.POSITIVE_INFINITY
        val dialect = Dialect.detect(header)
        files.csv(path, dialect.separator.code.toByte(), dialect.decimalComma).use { csv ->
            if (!csv.nextLine()) return Double.POSITIVE_INFINITY
            val names = csv.names()
            val event = names.indexOf("event")
            val time = names.indexOf("experiment time")
            if (event < 0 || time < 0) return Double.POSITIVE_INFINITY
            var last = ""
            var end = Double.POSITIVE_INFINITY
            while (csv.nextLine()) {
                if (csv.count <= maxOf(event, time)) return Double.POSITIVE_INFINITY
                last = csv.text(event).trim()
                end = try { csv.parseDouble(time) } catch (e: dev.motionfusion.core.io.FieldError) { return Double.POSITIVE_INFINITY }
            }
            return if (last == "PAUSE" && end.isFinite()) end else Double.POSITIVE_INFINITY
        }
    }

    fun plan(files: FileSet, dir: String): ImportPlan {
        val notes = ArrayList<String>()
        val endS = experimentEnd(files, dir)
        val chosen = LinkedHashMap<Quantity, Pair<String, ColumnMap>>()
        val unusable = ArrayList<String>()
        for (path in files.filesIn(dir).filter(::isCsv)) {
            val headerLine = files.firstLine(path) ?: continue
            val header = parse(headerLine, path) ?: continue
            for (set in header.sets) {
                val stream = set.quantity.stream
                if (stream == null) {
                    unusable += "${path.substringAfterLast('/')} (${set.quantity.name.lowercase().replace('_', ' ')})"
                    continue
                }
                val scale = DoubleArray(3) { k ->
                    set.quantity.units[set.units[k]] ?: throw DataFormatException(files.displayName(path), 1, 0,
                        "column '${ByteCsvReader.escapedExcerpt(header.names[set.columns[k]])}': unit '${ByteCsvReader.escapedExcerpt(set.units[k])}' not understood " +
                            "(expected ${set.quantity.units.keys.filter { it.isNotEmpty() }.joinToString(" or ")})")
                }
                val map = ColumnMap(stream, path, header.dialect, header.time, false, set.columns, scale, endS)
                val previous = chosen[set.quantity]
                if (previous == null) {
                    chosen[set.quantity] = path to map
                } else {
                    // Two data sets of one sensor: prefer the file named after it (then a copy's name), say which was left out.
                    val (kept, dropped) = if (naming(path, set.quantity) > naming(previous.first, set.quantity)) {
                        chosen[set.quantity] = path to map
                        path to previous.first
                    } else {
                        previous.first to path
                    }
                    notes += "two ${set.quantity.name.lowercase().replace('_', ' ')} data sets: ${kept.substringAfterLast('/')} used, ${dropped.substringAfterLast('/')} ignored (another recording? name the file to read it)"
                }
            }
        }
        val where = if (dir.isEmpty()) files.name else files.displayName(dir.removeSuffix("/"))
        val hint = if (unusable.isEmpty()) "" else "; found only ${unusable.joinToString(", ")}, which cannot stand in for it"
        if (Quantity.ACCELERATION !in chosen) {
            throw DataFormatException(where, 0, 0, "phyphox export without accelerometer data (Acceleration x (m/s^2) … with gravity)$hint: the filter needs it")
        }
        if (Quantity.GYROSCOPE !in chosen) {
            throw DataFormatException(where, 0, 0, "phyphox export without gyroscope data (Gyroscope x (rad/s) …): nothing to replay")
        }
        return ImportPlan(chosen.values.map { (_, m) -> StreamSource(m.stream) { f -> m.open(f) } }, notes)
    }
}
