package dev.motionfusion.app.i18n

/**
 * Finds words written into the app's Kotlin where a user sees them: a string literal with a letter
 * in it inside the expression handed to a text sink (a view's text, hint, error or
 * contentDescription, a dialog's title, message or buttons, a notification's texts or actions, an
 * accessibility announcement, a Toast or Snackbar, a text drawn on a canvas). Templates (`$x`,
 * `${…}`), escapes and format specifiers are not words; a text built elsewhere and passed by name
 * is not seen (the scan is precise, not complete: the German screens catch the rest).
 */
internal object LiteralTexts {
    /** Calls whose arguments are shown to the user. */
    private val CALLS = listOf(
        "setText", "setTextIfChanged", "setContentDescription", "announceForAccessibility", "setHint", "setError",
        "setStateDescription", "setTooltipText", "setTitle", "setMessage", "setPositiveButton", "setNegativeButton",
        "setNeutralButton", "setContentTitle", "setContentText", "setSubText", "setTicker", "bigText", "addAction",
        "makeText", "make", "drawText", "update",
    )

    /** Properties whose value is shown to the user. */
    private val PROPERTIES = listOf("text", "contentDescription", "hint", "error", "title", "tooltipText", "stateDescription")

    private val call = Regex("""(?<![\w.])(?:[\w.]*\.)?(${CALLS.joinToString("|")})\s*\(""")
    private val property = Regex("""(?<!\bva[lr] )(?<![\w])(?:[\w.]*\.)?(${PROPERTIES.joinToString("|")})\s*=(?!=)""")

    /** One finding: file, line (1-based), the sink and the literal. */
    data class Finding(val file: String, val line: Int, val sink: String, val literal: String) {
        override fun toString() = "$file:$line: \"$literal\" handed to $sink"
    }

    fun scan(source: String, file: String): List<Finding> {
        val code = stripComments(source)
        val out = ArrayList<Finding>()
        for (m in call.findAll(code)) {
            val open = m.range.last
            val end = matching(code, open)
            val sink = m.groupValues[1]
            // DescriptionThrottle.update(view, text, …) is a sink; other update(…) calls (flows) take lambdas, not texts.
            if (sink == "update" && !code.substring(maxOf(0, m.range.first - 40), m.range.last).contains("Description")) continue
            literals(code, open + 1, end, file, sink, out)
        }
        for (m in property.findAll(code)) {
            val start = m.range.last + 1
            literals(code, start, endOfExpression(code, start), file, m.groupValues[1] + " =", out)
        }
        return out.sortedBy { it.line }
    }

    /** The literals with words between [from] and [to]. */
    private fun literals(code: String, from: Int, to: Int, file: String, sink: String, out: MutableList<Finding>) {
        var i = from
        while (i < to) {
            val c = code[i]
            if (c == '"') {
                val close = closingQuote(code, i)
                val literal = code.substring(i + 1, close)
                if (hasWords(literal)) out += Finding(file, code.substring(0, i).count { it == '\n' } + 1, sink, literal)
                i = close + 1
            } else if (c == '\'') {
                i = closingChar(code, i) + 1
            } else {
                i++
            }
        }
    }

    /** Whether [literal] (the text between its quotes) holds a word once templates, escapes and format specifiers are removed. */
    fun hasWords(literal: String): Boolean {
        var s = removeTemplates(literal)
        s = s.replace(Regex("""\\u[0-9A-Fa-f]{4}|\\."""), " ")
        s = s.replace(Regex("""%(\d+\$)?[-#+ 0,(]*\d*(\.\d+)?[a-zA-Z%]"""), " ")
        return s.any { it.isLetter() }
    }

    private fun removeTemplates(s: String): String {
        val b = StringBuilder()
        var i = 0
        while (i < s.length) {
            if (s[i] == '$' && i + 1 < s.length && s[i + 1] == '{') {
                var depth = 0
                var j = i + 1
                while (j < s.length) {
                    if (s[j] == '{') depth++
                    if (s[j] == '}') { depth--; if (depth == 0) break }
                    j++
                }
                i = j + 1
            } else if (s[i] == '$' && i + 1 < s.length && (s[i + 1].isLetter() || s[i + 1] == '_')) {
                i++
                while (i < s.length && (s[i].isLetterOrDigit() || s[i] == '_')) i++
            } else {
                b.append(s[i]); i++
            }
        }
        return b.toString()
    }

    /** The index of the quote closing the literal opened at [open] (templates may hold quotes). */
    private fun closingQuote(code: String, open: Int): Int {
        var i = open + 1
        var braces = 0
        while (i < code.length) {
            val c = code[i]
            when {
                c == '\\' -> i++
                c == '$' && i + 1 < code.length && code[i + 1] == '{' -> { braces++; i++ }
                c == '}' && braces > 0 -> braces--
                c == '"' && braces == 0 -> return i
                c == '"' && braces > 0 -> i = closingQuote(code, i)
            }
            i++
        }
        return code.length
    }

    /** The index of the quote closing the char literal opened at [open]. */
    private fun closingChar(code: String, open: Int): Int =
        code.indexOf('\'', open + if (open + 1 < code.length && code[open + 1] == '\\') 3 else 2).let { if (it < 0) code.length - 1 else it }

    /** The index of the bracket closing the one at [open], skipping literals. */
    private fun matching(code: String, open: Int): Int = end(code, open + 1, atSeparator = false)

    /** Where an assignment's expression starting at [from] ends: a line end, a ';' or a ',' outside brackets, or a closing bracket. */
    private fun endOfExpression(code: String, from: Int): Int = end(code, from, atSeparator = true)

    /** The first closing bracket from [from] without its opening one (and with [atSeparator] a line end, ';' or ','), outside brackets and literals. */
    private fun end(code: String, from: Int, atSeparator: Boolean): Int {
        var depth = 0
        var i = from
        while (i < code.length) {
            when (code[i]) {
                '"' -> i = closingQuote(code, i)
                '\'' -> i = closingChar(code, i)
                '(', '[', '{' -> depth++
                ')', ']', '}' -> { if (depth == 0) return i; depth-- }
                '\n', ';', ',' -> if (atSeparator && depth == 0) return i
            }
            i++
        }
        return code.length
    }

    /** [source] with comments blanked out (line breaks kept, so line numbers stay right). */
    fun stripComments(source: String): String {
        val b = StringBuilder(source.length)
        var i = 0
        while (i < source.length) {
            val c = source[i]
            when {
                c == '"' -> {
                    val close = closingQuote(source, i).coerceAtMost(source.length - 1)
                    b.append(source, i, close + 1); i = close + 1
                }
                c == '\'' -> {
                    val close = closingChar(source, i)
                    b.append(source, i, close + 1); i = close + 1
                }
                c == '/' && i + 1 < source.length && source[i + 1] == '/' -> {
                    while (i < source.length && source[i] != '\n') i++
                }
                c == '/' && i + 1 < source.length && source[i + 1] == '*' -> {
                    val end = source.indexOf("*/", i + 2).let { if (it < 0) source.length else it + 2 }
                    for (k in i until end) if (source[k] == '\n') b.append('\n')
                    i = end
                }
                else -> { b.append(c); i++ }
            }
        }
        return b.toString()
    }
}
