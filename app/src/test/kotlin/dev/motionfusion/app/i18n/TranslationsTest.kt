package dev.motionfusion.app.i18n

import dev.motionfusion.app.build.BuildFiles
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.w3c.dom.Element
import java.io.File
import javax.xml.parsers.DocumentBuilderFactory

/**
 * Every language the app ships (German, values-de) has every text of the English one (values/),
 * with the same arguments in each (a missing or extra %1$s crashes or loses a figure at run time),
 * and every plural the quantities its language needs; no text is left in a translation that the
 * English no longer has.
 */
class TranslationsTest {
    private val res = File(BuildFiles.repositoryRoot, "app/src/main/res")

    /** Name → text (a plural's items joined) of the resources of [dir], plurals as "plurals/name". */
    internal data class Texts(val strings: Map<String, String>, val plurals: Map<String, Map<String, String>>)

    private fun read(dir: File): Texts {
        val strings = LinkedHashMap<String, String>()
        val plurals = LinkedHashMap<String, Map<String, String>>()
        for (f in dir.listFiles()!!.filter { it.extension == "xml" }.sortedBy { it.name }) {
            val doc = DocumentBuilderFactory.newInstance().newDocumentBuilder().parse(f).documentElement
            val nodes = doc.childNodes
            for (i in 0 until nodes.length) {
                val e = nodes.item(i) as? Element ?: continue
                if (e.getAttribute("translatable") == "false") continue
                when (e.tagName) {
                    "string" -> strings[e.getAttribute("name")] = e.textContent
                    "plurals" -> {
                        val items = e.getElementsByTagName("item")
                        plurals[e.getAttribute("name")] = (0 until items.length).associate { k -> (items.item(k) as Element).let { it.getAttribute("quantity") to it.textContent } }
                    }
                }
            }
        }
        return Texts(strings, plurals)
    }

    /** The differences of [translation] ([language], needing [quantities] in plurals) from [english]. */
    internal fun problems(english: Texts, translation: Texts, language: String, quantities: Set<String>): List<String> {
        val out = ArrayList<String>()
        for ((name, text) in english.strings) {
            val t = translation.strings[name]
            if (t == null) out += "$language lacks string $name" else if (arguments(t) != arguments(text)) out += "$language $name: arguments ${arguments(t)} ≠ ${arguments(text)}"
        }
        for (name in translation.strings.keys - english.strings.keys) out += "$language has string $name, which English has not"
        for ((name, items) in english.plurals) {
            val t = translation.plurals[name]
            if (t == null) { out += "$language lacks plurals $name"; continue }
            for (q in quantities) if (q !in t) out += "$language plurals $name lacks quantity $q"
            val args = arguments(items.getValue("other"))
            for ((q, text) in t) if (arguments(text) != args && arguments(text) != args - args.filter { it.startsWith("%d") }.toSet()) out += "$language plurals $name/$q: arguments ${arguments(text)} ≠ $args"
        }
        for (name in translation.plurals.keys - english.plurals.keys) out += "$language has plurals $name, which English has not"
        return out
    }

    /** The format arguments of [text]: position and conversion ("%1\$s", "%2\$f", "%d"), flags and widths aside. */
    internal fun arguments(text: String): Set<String> =
        Regex("""%(\d+\$)?[-#+ 0,(]*\d*(\.\d+)?([a-zA-Z])""").findAll(text.replace("%%", "")).map { "%" + it.groupValues[1] + it.groupValues[3].lowercase() }.toSet()

    @Test
    fun `German has every text of the English, with the same arguments and its plurals`() {
        val english = read(File(res, "values"))
        assertTrue(english.strings.size > 300, "${english.strings.size} English strings")
        assertEquals("", problems(english, read(File(res, "values-de")), "de", setOf("one", "other")).joinToString("\n"))
    }

    @Test
    fun `a missing text, a lost argument, a missing quantity and a stale text are each found`() {
        val english = Texts(mapOf("a" to "%1\$s of %2\$d", "b" to "B"), mapOf("p" to mapOf("one" to "%d item", "other" to "%d items")))
        val german = Texts(mapOf("a" to "%1\$s von", "old" to "alt"), mapOf("p" to mapOf("other" to "%d Dinge")))
        assertEquals(
            listOf(
                "de a: arguments [%1\$s] ≠ [%1\$s, %2\$d]", "de lacks string b", "de has string old, which English has not",
                "de plurals p lacks quantity one",
            ),
            problems(english, german, "de", setOf("one", "other")),
        )
    }
}
