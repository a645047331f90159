package dev.motionfusion.app.i18n

import dev.motionfusion.app.build.BuildFiles
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.io.File

/**
 * No words are written into the app's code or layouts where the user sees them: each is a string
 * resource, so that every language gets it ([LiteralTexts] for the Kotlin, [layoutLiterals] for
 * the XML). The snippets show that each kind of sink is found, and that what is not a word is not.
 */
class LiteralTextsTest {
    private val main = File(BuildFiles.repositoryRoot, "app/src/main")

    @Test
    fun `the app's Kotlin hands no literal text to a view, dialog, notification or announcement`() {
        val sources = File(main, "kotlin").walkTopDown().filter { it.isFile && it.extension == "kt" }.toList()
        assertTrue(sources.size > 50, "${sources.size} sources under $main")
        val findings = sources.flatMap { LiteralTexts.scan(it.readText(), it.relativeTo(main).path) }
        assertEquals("", findings.joinToString("\n"))
    }

    @Test
    fun `the layouts and menus name every text and description by resource`() {
        val files = File(main, "res").listFiles()!!.filter { it.name.startsWith("layout") || it.name.startsWith("menu") }.flatMap { it.listFiles()!!.toList() }
        assertTrue(files.size > 10)
        assertEquals("", files.flatMap { f -> layoutLiterals(f.readText()).map { "${f.parentFile.name}/${f.name}: $it" } }.joinToString("\n"))
    }

    @Test
    fun `each kind of sink with a word in it is found`() {
        val bad = mapOf(
            "status.text = \"Idle\"" to "text =",
            "v.setText(\"Hello \$name\")" to "setText",
            "contentDescription = \"\${held.size} of 6 faces held\"" to "contentDescription =",
            "Toast.makeText(this, \"Saved\", Toast.LENGTH_SHORT).show()" to "makeText",
            "builder.setContentTitle(\"Recording\")" to "setContentTitle",
            "view.announceForAccessibility(\"Recording started\")" to "announceForAccessibility",
            "t.setText(getString(R.string.calibration_refused, \"magnetometer\", f.reason))" to "setText",
            "canvas.drawText(\"N\", x, y, paint)" to "drawText",
            "MaterialAlertDialogBuilder(this).setTitle(\"Delete?\")" to "setTitle",
            "status.setTextIfChanged(\n    when (s) {\n        is Idle -> getString(R.string.x)\n        else -> \"Not recording\"\n    },\n)" to "setTextIfChanged",
            "anglesDescription.update(view, \"Angles \$a\", t)" to "update",
            "line2.text = items.joinToString(\"   \") { \"\${it.name} \${\"%.0f\".format(it.hz)} Hz\" }" to "text =",
        )
        for ((code, sink) in bad) {
            val found = LiteralTexts.scan(code, "Snippet.kt")
            assertEquals(1, found.size, "$code: $found")
            assertEquals(sink, found.single().sink, code)
        }
    }

    @Test
    fun `resources, formats, separators, templates and comments are not words`() {
        val fine = listOf(
            "status.text = getString(R.string.record_idle)",
            "rvDifference.text = lines.joinToString(\"\\n\")",
            "line.text = \"\$counts · \$extra\"",
            "value.text = \"%.1f\".format(Locale.ROOT, v) + \"°\"",
            "// status.text = \"a comment\"",
            "/* setText(\"a block comment\") */ x = 1",
            "val text = \"not shown: a local\"",
            "private val text = Paint(Paint.ANTI_ALIAS_FLAG).apply { textSize = 12f }",
            "_state.update { it.copy(saved = true, saveError = null) }",
            "canvas.drawText(\"\$deg°\", x, y, label)",
            "canvas.drawText(\"✓\", x, y, text)",
            "if (a == b) text = other",
        )
        for (code in fine) assertEquals(emptyList<LiteralTexts.Finding>(), LiteralTexts.scan(code, "Snippet.kt"), code)
    }

    @Test
    fun `a layout with a written text or description is found`() {
        val xml = """
            <TextView android:text="@string/ok" android:contentDescription="@string/x"/>
            <Button android:text="Record" tools:text="Sample"/>
            <ImageView android:contentDescription="Settings"/>
            <EditText android:hint=""/>
            <item android:title="Calibrate" app:title="@string/y"/>
        """.trimIndent()
        assertEquals(listOf("android:text=\"Record\"", "android:contentDescription=\"Settings\"", "android:title=\"Calibrate\""), layoutLiterals(xml))
    }

    companion object {
        private val ATTRIBUTE = Regex("""(android|app):(text|contentDescription|hint|title|tooltipText|stateDescription)="([^"]*)"""")

        /** The attributes of [xml] that write a text rather than name a resource (empty and `@null` are no text). */
        fun layoutLiterals(xml: String): List<String> =
            ATTRIBUTE.findAll(xml).filter { m -> m.groupValues[3].let { it.isNotEmpty() && !it.startsWith("@") && !it.startsWith("?") } }.map { it.value }.toList()
    }
}
