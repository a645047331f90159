package dev.motionfusion.core.io

/**
 * Splits one line of comma-separated values into fields without copying, remembering where
 * each field starts so errors can name the column. Quoted fields ("a,b") are supported for
 * headers; numbers are parsed from the field bounds.
 */
internal class CsvLine(private val separator: Char = ',') {
    private var line: String = ""
    private var starts = IntArray(16)
    private var ends = IntArray(16)

    /** Number of fields in the last split line. */
    var count: Int = 0
        private set

    fun split(text: String) {
        line = text
        count = 0
        var i = 0
        val n = text.length
        while (true) {
            if (count == starts.size) {
                starts = starts.copyOf(count * 2)
                ends = ends.copyOf(count * 2)
            }
            var start = i
            var end: Int
            if (i < n && text[i] == '"') {
                val close = text.indexOf('"', i + 1)
                start = i + 1
                end = if (close < 0) n else close
                i = if (close < 0) n else close + 1
                while (i < n && text[i] != separator) i++
            } else {
                while (i < n && text[i] != separator) i++
                end = i
            }
            starts[count] = start
            ends[count] = end
            count++
            if (i >= n) break
            i++ // skip the separator
        }
    }

    /** 0-based character offset of field [i] in the line. */
    fun start(i: Int): Int = starts[i]

    fun text(i: Int): String = line.substring(starts[i], ends[i])

    /**
     * Field [i] as a double. Empty gives NaN when [emptyIsNaN]. Accepts decimal numbers
     * ('.' as separator, optional exponent), NaN and Infinity; anything else (hexadecimal,
     * type suffixes, a decimal comma) throws [FieldError] with the reason.
     */
    fun parseDouble(i: Int, emptyIsNaN: Boolean): Double {
        var s = starts[i]
        var e = ends[i]
        while (s < e && line[s] == ' ') s++
        while (e > s && line[e - 1] == ' ') e--
        if (s == e) {
            if (emptyIsNaN) return Double.NaN
            throw FieldError("empty field, expected a number")
        }
        val last = line[e - 1]
        var foreign = last == 'd' || last == 'D' || last == 'f' || last == 'F' // Java type suffixes
        for (k in s until e) {
            val c = line[k]
            if (c == 'x' || c == 'X' || c == 'p' || c == 'P') foreign = true // hexadecimal floats
        }
        if (foreign) throw FieldError("'${line.substring(s, e)}' is not a decimal number")
        return line.substring(s, e).toDoubleOrNull() ?: throw FieldError("'${line.substring(s, e)}' is not a number")
    }
}

/** A field that is not what its column needs; the caller adds the file, line and column. */
internal class FieldError(val reason: String) : RuntimeException(reason, null, false, false)
