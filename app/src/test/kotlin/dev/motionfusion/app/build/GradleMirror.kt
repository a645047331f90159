package dev.motionfusion.app.build

import dev.motionfusion.app.build.BuildFiles.child
import dev.motionfusion.app.build.BuildFiles.children
import dev.motionfusion.app.build.BuildFiles.text
import dev.motionfusion.app.build.KotlinDsl.Assign
import dev.motionfusion.app.build.KotlinDsl.Binary
import dev.motionfusion.app.build.KotlinDsl.Call
import dev.motionfusion.app.build.KotlinDsl.Member
import dev.motionfusion.app.build.KotlinDsl.Name
import dev.motionfusion.app.build.KotlinDsl.Node
import dev.motionfusion.app.build.KotlinDsl.Str
import dev.motionfusion.app.build.KotlinDsl.literal
import dev.motionfusion.app.build.KotlinDsl.path
import org.w3c.dom.Element
import java.io.File
import java.util.Properties
import java.util.zip.ZipFile

/**
 * Compares the Android Studio project (settings.gradle.kts, the build.gradle.kts files,
 * gradle.properties, gradle/libs.versions.toml, the wrapper) with the Maven build of record under
 * [root] and lists what would make `./gradlew assembleDebug assembleRelease testDebugUnitTest
 * :fusion-core:test :fusion-stream:test :fusion-cli:test` fail or run differently from `mvn verify`: missing modules,
 * dependencies or versions; Surefire system properties, JVM flags and filtered resources without a
 * Gradle counterpart; test sources importing what only Maven puts on the test class path; Kotlin
 * compiler arguments; the debug key; the R8 that the release build runs against the Kotlin version
 * (gradle/compatibility.tsv); the AndroidX flag, the daemon's heap, the toolchain resolver, the
 * JUnit launcher; the wrapper's checksum and launchers. Everything is read from the files, so a
 * change to a pom (a property, a Surefire flag, an SDK level) is asked of the Gradle files too.
 *
 * [localRepository] holds the jars of Maven-only test dependencies, whose packages a test source
 * must then not import.
 */
internal class GradleMirror(
    private val root: File,
    private val localRepository: File?,
    /** Maven modules without a Gradle counterpart, and why. */
    private val mavenOnlyModules: Map<String, String> = MAVEN_ONLY_MODULES,
    /** Maven test dependencies Gradle leaves out, and why: no Gradle test source may import them. */
    private val mavenOnlyDependencies: Map<String, String> = emptyMap(),
    /** Surefire system properties that exist only in the Maven build, and why: tests reading them are excluded under Gradle. */
    private val mavenOnlyProperties: Map<String, String> = MAVEN_ONLY_PROPERTIES,
) {
    companion object {
        val MAVEN_ONLY_MODULES = mapOf(
            "android-libs" to "Maven's way to resolve AARs; Gradle resolves the app's dependencies itself",
            "android-test-libs" to "as android-libs, for the tests",
            "fusion-bench" to "JMH over the app module's classes, which Gradle does not offer to a JVM module",
        )
        val MAVEN_ONLY_PROPERTIES = mapOf(
            "android.libraries" to "the AARs android-libs unpacks for the Maven build; the Android Gradle Plugin merges libraries itself",
            "maven.repo.local" to "the local Maven repository whose POMs the tests of the Maven build read",
            "maven.build.directory" to "the Maven build's output folder, whose APKs MavenApkTest reads after packaging",
        )
        private const val LAUNCHER = "org.junit.platform:junit-platform-launcher"
        private const val FOOJAY = "org.gradle.toolchains.foojay-resolver-convention"
    }

    private val problems = ArrayList<String>()
    private fun problem(s: String) { problems += s }

    fun problems(): List<String> {
        problems.clear()
        val checks = listOf(
            ::modules, ::dependencies, ::versionsAndToolchain, ::androidSettings, ::gradleProperties, ::junitLauncher,
            ::testTasks, ::testSourceImports, ::filteredResources, ::kotlinArguments, ::debugKey, ::r8AndKotlin, ::wrapper,
            ::workflow, ::releaseShrinking, ::wrapperRelease, ::packagingExcludes, ::signingConfigs, ::releasesExist,
            ::metadataSources, ::managedVersions, ::cacheableTestInputs,
        )
        for (check in checks) {
            try { check() } catch (e: KotlinDsl.SyntaxError) { problem(e.message!!) } catch (e: MissingFile) { problem(e.message!!) }
        }
        return problems.distinct()
    }

    private class MissingFile(message: String) : RuntimeException(message)

    private fun file(path: String): File = File(root, path).also { if (!it.isFile) throw MissingFile("$path is missing") }

    // --- Maven side ---

    private fun pom(module: String?): Element = BuildFiles.parse(file(if (module == null) "pom.xml" else "$module/pom.xml"))

    private fun Element.properties(): Map<String, String> =
        child("properties")?.children()?.associate { it.tagName to it.textContent.trim() }.orEmpty()

    private val rootPom by lazy { pom(null) }

    /** The modules both builds have: the root pom's, without the Maven-only ones (a new module is checked without naming it here). */
    private val sharedModules: List<String> by lazy { rootPom.child("modules")!!.children("module").map { it.textContent.trim() } - mavenOnlyModules.keys }

    /** The plain JVM modules (all but the app). */
    private val jvmModules: List<String> get() = sharedModules - "app"
    private val rootProperties by lazy { rootPom.properties() + mapOf("project.version" to rootPom.text("version")!!) }

    private fun props(module: String) = rootProperties + pom(module).properties()

    private fun interpolate(value: String, props: Map<String, String>): String =
        Regex("""\$\{([^}]+)}""").replace(value) { m -> props[m.groupValues[1]] ?: m.value }

    private val managed by lazy {
        rootPom.child("dependencyManagement")!!.child("dependencies")!!.children("dependency")
            .associate { "${it.text("groupId")}:${it.text("artifactId")}" to interpolate(it.text("version")!!, rootProperties) }
    }

    private fun Element.plugins(): List<Element> = child("build")?.child("plugins")?.children("plugin").orEmpty()

    private fun rootPlugin(artifact: String) =
        rootPom.child("build")!!.child("pluginManagement")!!.child("plugins")!!.children("plugin").singleOrNull { it.text("artifactId") == artifact }

    private fun modulePlugin(module: String, artifact: String) = pom(module).plugins().singleOrNull { it.text("artifactId") == artifact }

    data class Dep(val configuration: String, val coordinates: String, val version: String) {
        override fun toString() = "$configuration $coordinates:$version"
    }

    private fun mavenDependencies(module: String): Set<Dep> {
        val pom = pom(module)
        val props = props(module)
        val out = HashSet<Dep>()
        for (d in pom.child("dependencies")!!.children("dependency")) {
            val ga = "${d.text("groupId")}:${d.text("artifactId")}"
            val scope = d.text("scope") ?: "compile"
            val version = d.text("version")?.let { interpolate(it, props) }
                ?: managed[ga]
                ?: (if (ga.startsWith("org.junit.")) managed["org.junit:junit-bom"] else null)
                ?: error("$module: no version for $ga")
            if (ga in mavenOnlyDependencies) continue
            if (scope == "provided" && ga == "org.robolectric:android-all") continue // the framework compiled against: compileSdk
            val configuration = when {
                d.text("type") == "signature" -> "apiSignature"
                scope == "test" -> "testImplementation"
                scope == "runtime" -> "runtimeOnly"
                else -> "implementation"
            }
            if (ga.startsWith("dev.motionfusion:android-")) {
                // The AndroidX lists: what the app asks for, at the versions the lists give.
                val libs = pom(ga.substringAfter(':'))
                val versions = libs.child("dependencies")!!.children("dependency")
                    .associate { "${it.text("groupId")}:${it.text("artifactId")}" to it.text("version")!! }
                for (used in libs.properties().getValue("app.uses").split(',')) out += Dep(configuration, used, versions.getValue(used))
            } else {
                out += Dep(configuration, ga, version)
            }
        }
        return out
    }

    /** Surefire's configuration for [module]: the module's own over the root's pluginManagement. */
    private fun surefire(module: String): Pair<Map<String, String>, List<String>> {
        val props = props(module) + mapOf("project.basedir" to "\${project.basedir}")
        val configs = listOfNotNull(rootPlugin("maven-surefire-plugin"), modulePlugin(module, "maven-surefire-plugin")).mapNotNull { it.child("configuration") }
        val system = LinkedHashMap<String, String>()
        var argLine = ""
        for (c in configs) {
            c.child("systemPropertyVariables")?.children()?.forEach { system[it.tagName] = it.textContent.trim() }
            c.text("argLine")?.let { argLine = it }
        }
        return system.mapValues { interpolate(it.value, props) } to argLine.split(Regex("\\s+")).filter { it.isNotEmpty() }
    }

    // --- Gradle side ---

    private val scripts = HashMap<String, List<Node>>()

    private fun script(path: String): List<Node> = scripts.getOrPut(path) { KotlinDsl.parse(file(path).readText(), path) }

    private fun moduleScript(module: String) = script("$module/build.gradle.kts")

    private fun calls(nodes: List<Node>): List<Pair<Call, List<Call>>> {
        val out = ArrayList<Pair<Call, List<Call>>>()
        KotlinDsl.walk(nodes) { n, outer -> if (n is Call) out += n to outer }
        return out
    }

    private fun assigns(nodes: List<Node>): List<Pair<Assign, List<Call>>> {
        val out = ArrayList<Pair<Assign, List<Call>>>()
        KotlinDsl.walk(nodes) { n, outer -> if (n is Assign) out += n to outer }
        return out
    }

    /** Names of the blocks around a node: `android`, `defaultConfig`, `tasks.withType<Test>().configureEach`… */
    private fun List<Call>.paths() = map { path(it.callee) + if (it.typeArgs.isEmpty()) "" else it.typeArgs.joinToString(",", "<", ">") }

    /** Inside a test task's configuration block. */
    private fun List<Call>.inTestTask(): Boolean = paths().any { p ->
        p == "tasks.test" || p.endsWith("withType<Test>().configureEach") || p.endsWith("withType<Test>") ||
            p.endsWith("named<Test>") || p == "unitTests.all" || p.endsWith(".configureEach") && p.contains("<Test>")
    } || any { c -> c.name == "configureEach" && path(c.callee).contains("withType<Test>") }

    private val toml: Map<String, Map<String, String>> by lazy {
        val sections = HashMap<String, MutableMap<String, String>>()
        var section = ""
        for (raw in file("gradle/libs.versions.toml").readLines()) {
            val line = raw.substringBefore('#').trim()
            if (line.isEmpty()) continue
            if (line.startsWith("[")) { section = line.trim('[', ']'); continue }
            sections.getOrPut(section) { LinkedHashMap() }[line.substringBefore('=').trim()] = line.substringAfter('=').trim()
        }
        sections
    }

    private fun tomlField(entry: String, field: String): String? = Regex("""$field\s*=\s*"([^"]*)"""").find(entry)?.groupValues?.get(1)

    private fun version(ref: String): String = toml["versions"]?.get(ref)?.trim('"') ?: error("no version $ref in libs.versions.toml")

    /** `libs.androidx.core.ktx` → coordinates and version (a BOM-managed library takes the BOM's version). */
    private fun library(accessor: String, bomVersion: String?): Pair<String, String> {
        val libs = toml["libraries"].orEmpty()
        val alias = libs.keys.singleOrNull { it.replace('-', '.').replace('_', '.') == accessor } ?: error("libs.$accessor is not in gradle/libs.versions.toml")
        val entry = libs.getValue(alias)
        val module = tomlField(entry, "module") ?: error("$alias: no module")
        val v = tomlField(entry, "version.ref")?.let(::version) ?: tomlField(entry, "version") ?: bomVersion ?: error("$alias: no version and no BOM")
        return module to v
    }

    private fun pluginId(accessor: String): Pair<String, String?> {
        val entry = toml["plugins"].orEmpty().entries.single { it.key.replace('-', '.') == accessor }.value
        return tomlField(entry, "id")!! to tomlField(entry, "version.ref")?.let(::version)
    }

    /** A dependency notation as Gradle reads it: `libs.x.y`, `project(":m")`, `platform(…)`, `variantOf(…) { }`, `"g:a:v"`. */
    private fun notation(n: Node, bom: String?, where: String): Pair<String, String>? = when {
        n is Member && path(n).startsWith("libs.") -> library(path(n).removePrefix("libs."), bom)
        n is Call && n.name == "project" -> "dev.motionfusion:${literal(n.args.single().value)!!.removePrefix(":")}" to rootProperties.getValue("project.version")
        n is Call && (n.name == "variantOf" || n.name == "platform") -> notation(n.args.first().value, bom, where)
        n is Str && n.plain -> n.text.split(':').let { "${it[0]}:${it[1]}" to it.getOrElse(2) { bom ?: "" }.substringBefore('@') }
        else -> { problem("$where: cannot read the dependency '${path(n)}'"); null }
    }

    private fun gradleDependencies(module: String): Set<Dep> {
        val where = "$module/build.gradle.kts"
        val blocks = moduleScript(module).filterIsInstance<Call>().filter { it.name == "dependencies" && it.callee is Name }
        val statements = blocks.flatMap { it.lambda!!.body }
        val bom = statements.filterIsInstance<Call>().firstOrNull { s -> s.args.firstOrNull()?.value.let { it is Call && it.name == "platform" } }
            ?.let { notation(it.args.first().value, null, where)?.second }
        val out = HashSet<Dep>()
        for (s in statements) {
            if (s is Call && s.name == "constraints" && s.args.isEmpty() && s.lambda != null) continue // constraints(): managedVersions
            if (s !is Call || s.callee !is Name || s.args.size != 1) { problem("$where:${s.line}: cannot read '${path(s)}' in dependencies"); continue }
            val arg = s.args.single().value
            if (arg is Call && arg.name == "platform") continue
            val (ga, v) = notation(arg, bom, "$where:${s.line}") ?: continue
            out += Dep(s.name, ga, v)
        }
        return out
    }

    // --- the checks ---

    private fun modules() {
        val maven = rootPom.child("modules")!!.children("module").map { it.textContent.trim() }.toSet() - mavenOnlyModules.keys
        val gradle = calls(script("settings.gradle.kts")).filter { it.first.name == "include" }
            .flatMap { it.first.args }.mapNotNull { literal(it.value)?.removePrefix(":") }.toSet()
        if (maven != gradle) problem("settings.gradle.kts includes $gradle; the Maven modules (without the Maven-only ones) are $maven")
    }

    /** The framework jars of the SDK matrix, one per API level (root pom's android.all.instrumented.N). */
    private val robolectricJars: Set<String> get() = rootProperties.filterKeys { it.startsWith("android.all.instrumented.") }
        .values.map { "org.robolectric:android-all-instrumented:$it" }.toSet()

    private fun dependencies() {
        for (module in sharedModules) {
            val gradle = gradleDependencies(module)
            val compared = gradle.filter { it.configuration in setOf("implementation", "runtimeOnly", "testImplementation", "apiSignature") }.toSet()
            val maven = mavenDependencies(module)
            for (d in maven - compared) problem("$module: Maven has $d, build.gradle.kts does not")
            for (d in compared - maven) problem("$module: build.gradle.kts has $d, Maven does not")
            for (d in gradle - compared) when (d.configuration) {
                "testRuntimeOnly" -> if (d.coordinates != LAUNCHER) problem("$module: testRuntimeOnly $d is not in the Maven build")
                "robolectricRuntime" -> if ("${d.coordinates}:${d.version}" !in robolectricJars) problem("$module: robolectricRuntime $d is not one of the framework jars Maven copies for Robolectric")
                else -> problem("$module: configuration ${d.configuration} ($d) has no Maven counterpart")
            }
            if (module == "app") {
                val copied = gradle.filter { it.configuration == "robolectricRuntime" }.map { "${it.coordinates}:${it.version}" }.toSet()
                for (jar in robolectricJars - copied) problem("app: robolectricRuntime lacks $jar, which Maven copies for the SDK matrix")
            }
        }
    }

    private fun versionsAndToolchain() {
        val (_, kotlin) = pluginId("kotlin.jvm")
        if (kotlin != rootProperties.getValue("kotlin.version")) problem("the Kotlin plugin is $kotlin in libs.versions.toml, Maven's kotlin.version is ${rootProperties["kotlin.version"]}")
        val target = rootProperties.getValue("kotlin.compiler.jvmTarget")
        var toolchains = false
        for (module in sharedModules) {
            val tc = calls(moduleScript(module)).filter { it.first.name == "jvmToolchain" }
            if (tc.isEmpty()) problem("$module/build.gradle.kts: no jvmToolchain($target) (Maven compiles for JVM $target)")
            for ((c, _) in tc) {
                toolchains = true
                val v = (c.args.singleOrNull()?.value as? KotlinDsl.Num)?.text
                if (v != target) problem("$module/build.gradle.kts:${c.line}: jvmToolchain($v), Maven's jvmTarget is $target")
            }
        }
        if (toolchains) {
            val plugins = script("settings.gradle.kts").filterIsInstance<Call>().filter { it.name == "plugins" }.flatMap { it.lambda!!.body }
            val foojay = plugins.any { p -> idOf(p) == FOOJAY }
            if (!foojay) problem("settings.gradle.kts: jvmToolchain is used but no toolchain resolver is applied (plugins { id(\"$FOOJAY\") }): a machine without that JDK fails to configure")
        }
    }

    /** `id("x") version "v"` or `id("x")` or `alias(libs.plugins.x)` → the plugin id. */
    private fun idOf(n: Node): String? = when {
        n is Binary && n.op == "version" -> idOf(n.left)
        n is Call && n.name == "id" -> literal(n.args.singleOrNull()?.value)
        n is Call && n.name == "alias" -> pluginId(path(n.args.single().value).removePrefix("libs.plugins.")).first
        else -> null
    }

    private fun assignedIn(module: String, name: String, vararg blocks: String): Node? =
        assigns(moduleScript(module)).firstOrNull { (a, outer) -> path(a.target) == name && blocks.all { b -> outer.any { path(it.callee) == b } } }?.first?.value

    private fun value(n: Node?): String? = when (n) {
        is Str -> n.text
        is KotlinDsl.Num -> n.text
        is Name -> n.name
        null -> null
        else -> path(n)
    }

    private fun androidSettings() {
        val props = props("app")
        val expect = mapOf(
            "namespace" to props.getValue("android.package"),
            "compileSdk" to props.getValue("android.compileSdk"),
        )
        for ((k, v) in expect) if (value(assignedIn("app", k, "android")) != v) problem("app/build.gradle.kts: android.$k is ${value(assignedIn("app", k, "android"))}, app/pom.xml says $v")
        val defaults = mapOf(
            "applicationId" to props.getValue("android.package"),
            "minSdk" to props.getValue("android.minSdk"),
            "targetSdk" to props.getValue("android.targetSdk"),
            "versionCode" to props.getValue("app.versionCode"),
            "versionName" to props.getValue("project.version"),
        )
        for ((k, v) in defaults) {
            val g = value(assignedIn("app", k, "android", "defaultConfig"))
            if (g != v) problem("app/build.gradle.kts: defaultConfig.$k is $g, the Maven build says $v")
        }
        val apiOfRelease = mapOf("13" to "33", "14" to "34", "15" to "35", "16" to "36")
        if (props.getValue("android.compileSdk") != apiOfRelease[props.getValue("android.all.version").substringBefore('-')]) problem("app/pom.xml: android-all's release is not compileSdk")
        // Folders: each folder Gradle names exists and the Maven build uses it.
        val appPom = file("app/pom.xml").readText()
        for ((c, _) in calls(moduleScript("app")).filter { it.first.name == "srcDirs" || it.first.name == "srcDir" || it.first.name == "srcFile" }) {
            for (a in c.args) {
                val dir = literal(a.value) ?: continue
                if (!File(root, "app/$dir").exists()) problem("app/build.gradle.kts:${c.line}: app/$dir does not exist")
                val maven = dir == "src/main/kotlin" || dir == "src/test/kotlin" || appPom.contains("\${project.basedir}/$dir") || appPom.contains("<directory>$dir</directory>")
                if (!maven) problem("app/build.gradle.kts:${c.line}: app/pom.xml does not use app/$dir")
            }
        }
        for (module in jvmModules) {
            val dirs = calls(moduleScript(module)).filter { it.first.name == "srcDirs" }.flatMap { it.first.args }.mapNotNull { literal(it.value) }.toSet()
            if (dirs != setOf("src/main/kotlin", "src/test/kotlin")) problem("$module/build.gradle.kts: source folders $dirs")
        }
    }

    private fun heapBytes(flag: String): Long? {
        val m = Regex("""-Xmx(\d+)([kKmMgG]?)""").matchEntire(flag) ?: return null
        val unit = when (m.groupValues[2].lowercase()) { "k" -> 1L shl 10; "m" -> 1L shl 20; "g" -> 1L shl 30; else -> 1L }
        return m.groupValues[1].toLong() * unit
    }

    private fun gradleProperties() {
        val f = File(root, "gradle.properties")
        if (!f.isFile) { problem("gradle.properties is missing: the Android Gradle Plugin refuses AndroidX dependencies without android.useAndroidX=true, and the daemon gets a small default heap"); return }
        val p = Properties().apply { f.reader().use { load(it) } }
        if (p.getProperty("android.useAndroidX") != "true") problem("gradle.properties: android.useAndroidX=true is not set (the app depends on AndroidX)")
        val heap = p.getProperty("org.gradle.jvmargs").orEmpty().split(Regex("\\s+")).firstNotNullOfOrNull(::heapBytes)
        // R8 in the daemon peaks at about 2.4 GB on the release build (measured under Maven).
        if (heap == null || heap < (3L shl 30)) problem("gradle.properties: org.gradle.jvmargs gives the daemon ${if (heap == null) "no -Xmx" else "${heap shr 20} MB"}; R8 needs at least -Xmx3g")
    }

    private fun junitLauncher() {
        for (module in sharedModules) {
            val deps = gradleDependencies(module)
            val platform = calls(moduleScript(module)).any { (c, outer) -> c.name == "useJUnitPlatform" && (outer.inTestTask() || path(c.callee).startsWith("it.")) }
            if (!platform) problem("$module/build.gradle.kts: its test task does not useJUnitPlatform()")
            if (deps.none { it.configuration == "testRuntimeOnly" && it.coordinates == LAUNCHER }) {
                problem("$module/build.gradle.kts: no testRuntimeOnly(\"$LAUNCHER\"): Gradle then puts its own older launcher beside JUnit ${rootProperties["junit.version"]} and discovery fails")
            }
        }
    }

    /** What the test tasks of a module's script set: system properties (name → literal value or null), JVM flags, max heap, excluded classes. */
    private data class TestConfig(val properties: Map<String, String?>, val jvmArgs: List<String>, val maxHeap: String?, val excluded: Set<String>)

    private fun testConfig(module: String): TestConfig {
        val properties = LinkedHashMap<String, String?>()
        val jvm = ArrayList<String>()
        var heap: String? = null
        val excluded = HashSet<String>()
        val nodes = moduleScript(module)
        // Helpers declared in the script (`fun Test.systemPropertyFile(…)`) count where they are called.
        val helpers = nodes.filterIsInstance<KotlinDsl.Decl>().filter { it.kind == "fun" }.map { it.name }.toSet()
        for ((c, outer) in calls(nodes)) {
            if (!outer.inTestTask()) continue
            when (c.name) {
                "systemProperty" -> literal(c.args.getOrNull(0)?.value)?.let { properties[it] = (c.args.getOrNull(1)?.value as? Str)?.takeIf { s -> s.plain }?.text }
                in helpers -> if (c.name.startsWith("systemProperty")) literal(c.args.getOrNull(0)?.value)?.let { properties[it] = null }
                "jvmArgs" -> c.args.forEach { a -> jvm += strings(a.value) }
                "excludeTestsMatching" -> c.args.mapNotNull { literal(it.value) }.forEach { excluded += it }
            }
        }
        for ((a, outer) in assigns(nodes)) {
            if (!outer.inTestTask()) continue
            if (path(a.target).endsWith("maxHeapSize")) heap = literal(a.value)
            if (path(a.target).endsWith("jvmArgs")) jvm += strings(a.value)
        }
        return TestConfig(properties, jvm, heap, excluded)
    }

    private fun strings(n: Node): List<String> = when {
        n is Str -> listOf(n.text)
        n is Call && n.name in setOf("listOf", "arrayOf", "mutableListOf") -> n.args.flatMap { strings(it.value) }
        else -> emptyList()
    }

    /** Property names the BuildFiles helper reads, by accessor (`val manifest: File get() = path("android.manifest")`). */
    private val accessors by lazy {
        val f = File(root, "app/src/test/kotlin/dev/motionfusion/app/build/BuildFiles.kt")
        if (!f.isFile) emptyMap() else Regex("""val (\w+): File get\(\) = path\("([^"]+)"\)""").findAll(f.readText()).associate { it.groupValues[2] to it.groupValues[1] }
    }

    private fun testSources(module: String): List<File> =
        File(root, "$module/src/test/kotlin").walk().filter { it.isFile && it.name.endsWith(".kt") }.toList()

    private fun className(module: String, f: File): String {
        val pkg = Regex("""(?m)^package ([\w.]+)""").find(f.readText())?.groupValues?.get(1)
        return listOfNotNull(pkg, f.nameWithoutExtension).joinToString(".")
    }

    private fun readsProperty(source: String, name: String): Boolean =
        source.contains("getProperty(\"$name\"") || accessors[name]?.let { Regex("""BuildFiles\.$it\b""").containsMatchIn(source) } == true

    private fun excludedUnderGradle(module: String, f: File): Boolean {
        val cls = className(module, f)
        return testConfig(module).excluded.any { it == cls || (it.endsWith("*") && cls.startsWith(it.removeSuffix("*"))) }
    }

    private fun testTasks() {
        for (module in sharedModules) {
            val (system, argLine) = surefire(module)
            val g = testConfig(module)
            val where = "$module/build.gradle.kts"
            for ((name, value) in system) {
                if (name in mavenOnlyProperties) {
                    for (f in testSources(module)) {
                        if (readsProperty(f.readText(), name) && !excludedUnderGradle(module, f)) {
                            problem("$where: ${f.relativeTo(root)} reads $name (Maven only: ${mavenOnlyProperties[name]}) and is not excluded from Gradle's test task (filter { excludeTestsMatching(\"${className(module, f)}\") })")
                        }
                    }
                    continue
                }
                if (name !in g.properties) { problem("$where: Surefire's system property $name has no systemProperty(\"$name\", …) in the test task"); continue }
                val literalValue = !value.contains("\${") && !value.contains('/')
                if (literalValue && g.properties[name] != value) problem("$where: systemProperty(\"$name\") is ${g.properties[name]}, Surefire gives $value")
            }
            for ((name, _) in g.properties) if (name !in system) problem("$where: the test task sets $name, which Surefire does not (${module}/pom.xml)")
            var i = 0
            while (i < argLine.size) {
                val flag = argLine[i]
                val heap = heapBytes(flag)
                when {
                    heap != null -> {
                        val gradleHeap = g.maxHeap?.let { heapBytes("-Xmx$it") } ?: g.jvmArgs.firstNotNullOfOrNull(::heapBytes)
                        if (gradleHeap != heap) problem("$where: Surefire runs the tests with $flag; the test task has ${g.maxHeap?.let { "maxHeapSize = \"$it\"" } ?: "no maxHeapSize"}")
                    }
                    flag.startsWith("--") && !flag.contains('=') && i + 1 < argLine.size -> {
                        val v = argLine[++i]
                        val ok = g.jvmArgs.zipWithNext().any { it == flag to v } || "$flag=$v" in g.jvmArgs
                        if (!ok) problem("$where: Surefire's JVM flag $flag $v is not in the test task's jvmArgs")
                    }
                    flag !in g.jvmArgs -> problem("$where: Surefire's JVM flag $flag is not in the test task's jvmArgs")
                }
                i++
            }
        }
    }

    private fun jarPackages(ga: String, version: String): Set<String>? {
        val repo = localRepository ?: return null
        val (g, a) = ga.split(':')
        val jar = File(repo, "${g.replace('.', '/')}/$a/$version/$a-$version.jar")
        if (!jar.isFile) return null
        return ZipFile(jar).use { z -> z.entries().asSequence().map { it.name }.filter { it.endsWith(".class") && '/' in it }.map { it.substringBeforeLast('/').replace('/', '.') }.toSet() }
    }

    private fun testSourceImports() {
        for (module in sharedModules) {
            val gradle = gradleDependencies(module).map { it.coordinates }.toSet()
            val missing = mavenDependencies(module).filter { it.coordinates !in gradle } +
                pom(module).child("dependencies")!!.children("dependency")
                    .filter { "${it.text("groupId")}:${it.text("artifactId")}" in mavenOnlyDependencies }
                    .map { Dep("test", "${it.text("groupId")}:${it.text("artifactId")}", interpolate(it.text("version") ?: "", props(module))) }
            for (dep in missing) {
                val packages = jarPackages(dep.coordinates, dep.version)
                if (packages == null) { if (dep.configuration != "apiSignature") problem("$module: ${dep.coordinates}:${dep.version} is not on Gradle's test class path and its jar is not in the local Maven repository to check imports against"); continue }
                // Every test source compiles under Gradle, the excluded ones too: excluding a class skips its run only.
                for (f in testSources(module)) {
                    for (imp in Regex("""(?m)^import ([\w.]+)""").findAll(f.readText()).map { it.groupValues[1] }) {
                        if (imp.substringBeforeLast('.') in packages || imp in packages) {
                            problem("${f.relativeTo(root)} imports $imp from ${dep.coordinates}, which only Maven puts on the test class path: under Gradle the test sources do not compile")
                        }
                    }
                }
            }
            // Maven's output layout named in a test: under Gradle the classes are under build/.
            for (f in testSources(module)) if (!excludedUnderGradle(module, f)) {
                val text = f.readText()
                for (layout in listOf("\"target/classes\"", "\"target/test-classes\"")) if (text.contains(layout)) {
                    problem("${f.relativeTo(root)} reads $layout, Maven's output folder: under Gradle it finds nothing (pass the folder as a system property)")
                }
            }
        }
    }

    /** Files of Maven's filtered resource folders that hold `${…}` and what stands for them under Gradle. */
    private fun filteredResources() {
        for (module in sharedModules) {
            val build = pom(module).child("build") ?: continue
            val filtered = (build.child("resources")?.children("resource").orEmpty().map { "main" to it } +
                build.child("testResources")?.children("testResource").orEmpty().map { "test" to it })
                .filter { it.second.text("filtering") == "true" }
            val nodes = moduleScript(module)
            for ((set, res) in filtered) {
                val dir = res.text("directory")!!
                val files = File(root, "$module/$dir").walk().filter { it.isFile && it.readText().contains("\${") }.toList()
                for (f in files) {
                    val rel = f.relativeTo(File(root, "$module/$dir")).invariantSeparatorsPath
                    val placeholders = Regex("""\$\{([^}]+)}""").findAll(f.readText()).map { it.groupValues[1] }.toSet()
                    if (module == "app") {
                        // The Android Gradle Plugin writes com/android/tools/test_config.properties itself when unit tests include Android resources.
                        val agp = rel == "com/android/tools/test_config.properties" &&
                            value(assignedIn("app", "unitTests.isIncludeAndroidResources", "android", "testOptions")) == "true"
                        val gradleDirsAll = calls(nodes).filter { path(it.first.callee) == "resources.srcDirs" }.flatMap { it.first.args }.mapNotNull { literal(it.value) }
                        if (dir in gradleDirsAll) problem("app/build.gradle.kts: $module/$dir/$rel is filtered by Maven (${placeholders.joinToString { "\${$it}" }}) but Gradle copies it unexpanded; keep it in a Maven-only folder")
                        else if (!agp) problem("$module/$dir/$rel: filtered by Maven, no Gradle counterpart")
                        continue
                    }
                    val task = if (set == "main") "tasks.processResources" else "tasks.processTestResources"
                    val expands = calls(nodes).filter { (c, outer) -> c.name == "expand" && outer.any { path(it.callee) == task } && outer.any { it.name == "filesMatching" && glob(literal(it.args.firstOrNull()?.value) ?: "", rel) } }
                    if (expands.isEmpty()) { problem("$module/build.gradle.kts: $dir/$rel is filtered by Maven (${placeholders.joinToString { "\${$it}" }}); $task has no filesMatching(…) { expand(…) } for it, so Gradle ships the placeholder"); continue }
                    val keys = expands.flatMap { (c, _) -> c.args.flatMap { pairs(it.value) } }
                    for (ph in placeholders) {
                        val head = ph.substringBefore('.')
                        val pair = keys.firstOrNull { it.first == head }
                        val sub = pair?.second?.let { v -> if (v is Call && v.name == "mapOf") v.args.flatMap { pairs(it.value) }.map { it.first } else null }
                        if (pair == null || (sub != null && ph.contains('.') && ph.substringAfter('.') !in sub)) problem("$module/build.gradle.kts: expand(…) does not give \${$ph} of $dir/$rel")
                    }
                }
            }
        }
    }

    private fun pairs(n: Node): List<Pair<String, Node>> = when {
        n is Binary && n.op == "to" -> listOfNotNull(literal(n.left)?.let { it to n.right })
        else -> emptyList()
    }

    private fun glob(pattern: String, path: String): Boolean {
        val rx = Regex(pattern.split("**/").joinToString("(.*/)?") { part -> part.split('*').joinToString("[^/]*") { Regex.escape(it) } })
        return rx.matches(path)
    }

    private fun kotlinArguments() {
        for (module in sharedModules) {
            val maven = LinkedHashSet<String>()
            val plugins = listOfNotNull(rootPlugin("kotlin-maven-plugin"), modulePlugin(module, "kotlin-maven-plugin"))
            for (p in plugins) {
                p.child("configuration")?.child("args")?.children("arg")?.forEach { maven += it.textContent.trim() }
                p.child("executions")?.children("execution")?.forEach { e -> e.child("configuration")?.child("args")?.children("arg")?.forEach { maven += it.textContent.trim() } }
            }
            val nodes = moduleScript(module)
            val gradle = HashSet<String>()
            for ((c, _) in calls(nodes)) {
                if (path(c.callee).endsWith("freeCompilerArgs.add") || path(c.callee).endsWith("freeCompilerArgs.addAll")) c.args.forEach { gradle += strings(it.value) }
                if (c.name == "explicitApi" && c.args.isEmpty()) gradle += "-Xexplicit-api=strict"
            }
            for ((a, _) in assigns(nodes)) if (path(a.target).endsWith("freeCompilerArgs")) gradle += strings(a.value)
            for (arg in maven - gradle) problem("$module/build.gradle.kts: Maven compiles Kotlin with $arg; the Gradle build does not (kotlin { compilerOptions { freeCompilerArgs.add(\"$arg\") } })")
        }
    }

    private fun debugKey() {
        val exec = modulePlugin("app", "exec-maven-plugin")!!.child("executions")!!.children("execution").single { it.text("id") == "apk-debug" }
        val args = exec.child("configuration")!!.child("arguments")!!.children("argument").map { it.textContent.trim() }
        val keystore = args[args.size - 3].replace("\${project.basedir}/", "")
        val password = args[args.size - 2]
        val alias = args[args.size - 1]
        val block = { name: String -> assigns(moduleScript("app")).firstOrNull { (a, outer) -> path(a.target) == name && outer.any { path(it.callee) == "signingConfigs.getByName" || (it.name == "getByName" && outer.any { o -> o.name == "signingConfigs" }) } }?.first?.value }
        val store = block("storeFile").let { if (it is Call && it.name == "file") literal(it.args.single().value) else null }
        val expect = mapOf("storeFile" to (store to keystore), "storePassword" to (literal(block("storePassword")) to password),
            "keyAlias" to (literal(block("keyAlias")) to alias), "keyPassword" to (literal(block("keyPassword")) to password))
        for ((k, v) in expect) if (v.first != v.second) problem("app/build.gradle.kts: the debug signingConfig's $k is ${v.first}; Maven signs debug builds with $keystore (alias $alias): installing one build over the other fails")
        if (!File(root, "app/$keystore").isFile) problem("app/$keystore is missing")
    }

    private fun compatibility(): List<List<String>> =
        file("gradle/compatibility.tsv").readLines().map { it.substringBefore('#').trim() }.filter { it.isNotEmpty() }.map { it.split(Regex("\\s+")) }

    private fun cmp(a: String, b: String): Int {
        val x = a.split('.', '-').map { it.toIntOrNull() ?: 0 }
        val y = b.split('.', '-').map { it.toIntOrNull() ?: 0 }
        for (i in 0 until maxOf(x.size, y.size)) { val d = x.getOrElse(i) { 0 }.compareTo(y.getOrElse(i) { 0 }); if (d != 0) return d }
        return 0
    }

    private fun minor(v: String) = v.split('.').take(2).joinToString(".")

    private fun r8AndKotlin() {
        val table = compatibility()
        val kotlin = rootProperties.getValue("kotlin.version")
        val agp = pluginId("android.application").second ?: error("no AGP version")
        val kotlinRow = table.firstOrNull { it[0] == "kotlin" && it[1] == minor(kotlin) }
            ?: return problem("gradle/compatibility.tsv has no row for Kotlin ${minor(kotlin)}")
        val agpRow = table.firstOrNull { it[0] == "agp" && it[1] == minor(agp) }
            ?: return problem("gradle/compatibility.tsv has no row for AGP ${minor(agp)}")
        val (minAgp, minR8) = kotlinRow[2] to kotlinRow[3]
        val (bundledR8, minGradle) = agpRow[2] to agpRow[3]
        if (cmp(agp, minAgp) < 0) problem("AGP $agp is older than Kotlin $kotlin needs ($minAgp, gradle/compatibility.tsv)")
        // The R8 the release build runs: the one R8's documentation has replace AGP's own, on the class path
        // of settings.gradle.kts' pluginManagement { buildscript { dependencies { classpath(…) } } }, else AGP's.
        val pinned = r8Pins("settings.gradle.kts", listOf("pluginManagement", "buildscript")).firstOrNull()
        // Elsewhere (the root buildscript, a module's) a pin only works, if at all, by class-path order: AGP's builder jar holds R8 too.
        for (where in listOf("build.gradle.kts") + sharedModules.map { "$it/build.gradle.kts" }) {
            if (r8Pins(where, listOf("buildscript")).isNotEmpty()) problem("$where pins com.android.tools:r8 in its buildscript: that R8 wins over the one inside AGP only by class-path order; pin it in settings.gradle.kts pluginManagement { buildscript { … } }, where R8's documentation puts it")
        }
        val r8 = pinned ?: bundledR8
        if (cmp(r8, minR8) < 0) problem("the release build's R8 is $r8 (${if (pinned == null) "bundled with AGP $agp" else "pinned in settings.gradle.kts"}), Kotlin $kotlin needs R8 $minR8 or newer (gradle/compatibility.tsv): pin com.android.tools:r8 in settings.gradle.kts pluginManagement { buildscript { dependencies { classpath(…) } } }")
        if (pinned != null && pinned != rootProperties["r8.version"]) problem("settings.gradle.kts pins R8 $pinned, Maven runs ${rootProperties["r8.version"]}")
        val gradle = Regex("""gradle-([\d.]+)-(bin|all)\.zip""").find(file("gradle/wrapper/gradle-wrapper.properties").readText())?.groupValues?.get(1)
        if (gradle == null || cmp(gradle, minGradle) < 0) problem("the wrapper's Gradle $gradle is older than AGP $agp needs ($minGradle)")
    }

    private fun wrapper() {
        val p = Properties().apply { file("gradle/wrapper/gradle-wrapper.properties").reader().use { load(it) } }
        val sum = p.getProperty("distributionSha256Sum")
        if (sum == null || !sum.matches(Regex("[0-9a-f]{64}"))) problem("gradle/wrapper/gradle-wrapper.properties: no distributionSha256Sum: the distribution is run without a check")
        val sh = file("gradlew").readText()
        if (!sh.contains("distributionSha256Sum") || !sh.contains("sha256")) problem("gradlew does not verify distributionSha256Sum")
        if (!File(root, "gradlew").canExecute()) problem("gradlew is not executable")
        val bat = file("gradlew.bat").readLines()
        for ((i, line) in bat.withIndex()) {
            if (Regex("(?i)powershell").containsMatchIn(line) && !line.trimStart().startsWith("@rem") && !line.trimStart().lowercase().startsWith("rem ")) {
                if (!Regex("(?i)-File\\s").containsMatchIn(line)) problem("gradlew.bat:${i + 1}: PowerShell is given its program on cmd's command line, where cmd strips its quotes; run a script file with -File")
                Regex("""-File\s+"%~dp0([^"]+)"""").find(line)?.groupValues?.get(1)?.let { ps -> if (!File(root, ps.replace('\\', '/')).isFile) problem("gradlew.bat:${i + 1}: $ps is missing") }
            }
        }
    }

    private fun workflow() {
        val f = File(root, ".github/workflows/gradle.yml")
        if (!f.isFile) return problem(".github/workflows/gradle.yml is missing: nothing runs the Gradle build")
        val text = f.readText()
        for (needed in listOf("actions/setup-java", "java-version: ${rootProperties["maven.compiler.release"]}", "gradle/actions/setup-gradle", "assembleDebug", "assembleRelease", "testDebugUnitTest") + jvmModules.map { ":$it:test" }) {
            if (!text.contains(needed)) problem(".github/workflows/gradle.yml does not have $needed")
        }
    }


    // --- what the Gradle files mean (issue 37): shrinking, the wrapper's release, packaging, signing,
    // versions that exist, metadata sources, managed versions, cacheable test inputs ---

    private fun r8Pins(path: String, blocks: List<String>): List<String> {
        if (!File(root, path).isFile) return emptyList()
        return calls(script(path)).filter { (c, outer) -> c.name == "classpath" && outer.map { it.name } == blocks + "dependencies" }
            .mapNotNull { (c, _) -> c.args.singleOrNull()?.value?.let { notation(it, null, path) } }
            .filter { it.first == "com.android.tools:r8" }.map { it.second }
    }

    /** The statements of the app's build type [name] (`getByName("release") { … }`, `release { … }` inside `buildTypes`). */
    private fun buildType(name: String): List<Node>? = calls(moduleScript("app")).firstOrNull { (c, outer) ->
        outer.any { it.name == "buildTypes" } && c.lambda != null &&
            ((c.name in setOf("getByName", "create", "named", "maybeCreate") && literal(c.args.firstOrNull()?.value) == name) || (c.name == name && c.args.isEmpty()))
    }?.first?.lambda?.body

    private fun assignedIn(nodes: List<Node>, name: String): Node? = assigns(nodes).firstOrNull { path(it.first.target) == name }?.first?.value

    private fun releaseShrinking() {
        val where = "app/build.gradle.kts"
        val release = buildType("release") ?: return problem("$where: no release build type")
        val minify = value(assignedIn(release, "isMinifyEnabled"))
        if (minify != "true") problem("$where: the release build type has isMinifyEnabled = ${minify ?: "(not set: false)"}; the Maven release build shrinks with R8 (tools/android-build.sh), so Gradle's release APK would carry every unused class and never run the pinned R8")
        val given = calls(release).filter { it.first.name == "proguardFiles" || it.first.name == "proguardFile" }.flatMap { it.first.args }
        val files = given.mapNotNull { literal(it.value) }
        // What the Maven release build gives R8 from the app's folder (besides aapt2's and the libraries' rules, which AGP adds itself).
        val maven = Regex("""--pg-conf "\${'$'}target/\.\./([^"]+)"""").findAll(file("tools/android-build.sh").readText()).map { it.groupValues[1] }.toSet()
        for (r in maven - files.toSet()) problem("$where: the release build type's proguardFiles do not name $r, which the Maven release build gives R8: its keep rules are lost under Gradle")
        for (f in files) if (!File(root, "app/$f").isFile) problem("$where: proguardFiles names app/$f, which does not exist")
    }

    private fun wrapperRelease() {
        val p = Properties().apply { file("gradle/wrapper/gradle-wrapper.properties").reader().use { load(it) } }
        val url = p.getProperty("distributionUrl") ?: return problem("gradle/wrapper/gradle-wrapper.properties: no distributionUrl")
        val m = Regex("""https://services\.gradle\.org/distributions/gradle-(\d[\w.\-]*)-(bin|all)\.zip""").matchEntire(url)
            ?: return problem("gradle/wrapper/gradle-wrapper.properties: distributionUrl $url is not a Gradle release on services.gradle.org")
        val (version, type) = m.destructured
        val releases = file("gradle/gradle-releases.tsv").readLines().map { it.substringBefore('#').trim() }.filter { it.isNotEmpty() }.map { it.split(Regex("\\s+")) }
        for (r in releases) if (r.size != 3 || !r[2].matches(Regex("[0-9a-f]{64}"))) problem("gradle/gradle-releases.tsv: '${r.joinToString(" ")}' is not VERSION TYPE SHA256")
        val row = releases.firstOrNull { it.size == 3 && it[0] == version && it[1] == type }
            ?: return problem("gradle/wrapper/gradle-wrapper.properties: Gradle $version ($type) is not in gradle/gradle-releases.tsv: add it with the SHA-256 Gradle publishes (https://services.gradle.org/distributions/gradle-$version-$type.zip.sha256)")
        val sum = p.getProperty("distributionSha256Sum") ?: return
        if (sum != row[2]) problem("gradle/wrapper/gradle-wrapper.properties: distributionSha256Sum $sum is not the SHA-256 Gradle publishes for gradle-$version-$type.zip (${row[2]}, gradle/gradle-releases.tsv): every download would be refused")
    }

    /** The app's Java resources a packaging exclude must not drop: the ServiceLoader files of its runtime jars. */
    private fun serviceFiles(): Set<String> {
        val found = HashSet<String>()
        for (d in mavenDependencies("app").filter { it.configuration == "implementation" }) {
            val repo = localRepository ?: break
            val (g, a) = d.coordinates.split(':')
            val jar = File(repo, "${g.replace('.', '/')}/$a/${d.version}/$a-${d.version}.jar")
            if (jar.isFile) ZipFile(jar).use { z -> z.entries().asSequence().map { it.name }.filter { it.startsWith("META-INF/services/") && !it.endsWith("/") }.forEach { found += it } }
        }
        // kotlinx-coroutines-android's, which Dispatchers.Main is found through, whether or not the jar is at hand.
        return found + "META-INF/services/kotlinx.coroutines.internal.MainDispatcherFactory"
    }

    /** AGP's glob (ParsedPackagingOptions): a pattern not starting with / or * is anchored at the archive's root. */
    internal fun packagingMatches(pattern: String, entry: String): Boolean {
        val glob = if (pattern.startsWith("/") || pattern.startsWith("*")) pattern else "/$pattern"
        return java.nio.file.FileSystems.getDefault().getPathMatcher("glob:$glob").matches(java.nio.file.Paths.get("/$entry"))
    }

    /** The `excludes` the app's `packaging { }` (or `packagingOptions { }`) adds, at any depth (`resources { }`, `jniLibs { }`). */
    internal fun packagingExcludesDeclared(): List<Pair<String, Int>> {
        val inPackaging = { outer: List<Call> -> outer.any { it.name == "packaging" || it.name == "packagingOptions" } }
        val out = ArrayList<Pair<String, Int>>()
        for ((a, outer) in assigns(moduleScript("app"))) if (inPackaging(outer) && path(a.target).endsWith("excludes")) strings(a.value).forEach { out += it to a.line }
        for ((c, outer) in calls(moduleScript("app"))) if (inPackaging(outer)) {
            val callee = path(c.callee)
            if (callee.endsWith("excludes.add") || callee.endsWith("excludes.addAll") || callee == "exclude") c.args.forEach { a -> strings(a.value).forEach { out += it to c.line } }
        }
        return out
    }

    private fun packagingExcludes() {
        val services = serviceFiles()
        for ((pattern, line) in packagingExcludesDeclared()) {
            val dropped = services.filter { packagingMatches(pattern, it) }
            if (dropped.isNotEmpty()) problem("app/build.gradle.kts:$line: packaging excludes \"$pattern\", which drops ${dropped.sorted().joinToString()}: ServiceLoader then finds nothing on the phone (Dispatchers.Main fails without kotlinx-coroutines-android's MainDispatcherFactory); the Maven build packages them")
        }
    }

    /** `signingConfigs.getByName("debug")`, `signingConfigs["debug"]`, `null` → "debug", "null". */
    private fun signingConfigName(n: Node?): String? = when {
        n == null -> null
        n is Name -> n.name
        n is Call && n.name in setOf("getByName", "get", "named") -> literal(n.args.firstOrNull()?.value)
        else -> path(n)
    }

    /** apksigner's scheme flags in tools/android-build.sh: 1..4 → enabled. */
    private fun apksignerSchemes(): Map<Int, Boolean?> {
        val text = file("tools/android-build.sh").readText()
        return (1..4).associateWith { n -> Regex("""--v$n-signing-enabled (true|false)""").find(text)?.groupValues?.get(1)?.toBoolean() }
    }

    private fun signingConfigs() {
        val where = "app/build.gradle.kts"
        val debug = buildType("debug")
        val debugConfig = debug?.let { signingConfigName(assignedIn(it, "signingConfig")) }
        // Unset, AGP signs the debug build type with the debug signingConfig; anything else is another key or none.
        if (debug != null && assignedIn(debug, "signingConfig") != null && debugConfig != "debug") problem("$where: the debug build type's signingConfig is $debugConfig: the debug APK is then ${if (debugConfig == "null") "not signed and does not install" else "signed with another key"}; the Maven build signs it with app/debug.keystore")
        val release = buildType("release")
        if (release != null && signingConfigName(assignedIn(release, "signingConfig")) == "debug") problem("$where: the release build type is signed with the debug key; the Maven release build refuses it")
        // The schemes: written out on both sides, and equal.
        val schemes = declaredSigningSchemes()
        val apksigner = apksignerSchemes()
        for (n in 1..4) {
            val declared = schemes.getValue(n)
            val maven = apksigner.getValue(n)
            when {
                maven == null -> problem("tools/android-build.sh: apksigner is not given --v$n-signing-enabled: its default and AGP's differ")
                declared == null -> problem("$where: the debug signingConfig does not set enableV${n}Signing: AGP's default and apksigner's (tools/android-build.sh: $maven) differ")
                declared != maven -> problem("$where: the debug signingConfig has enableV${n}Signing = $declared; the Maven build signs with --v$n-signing-enabled $maven")
            }
        }
    }

    /** The debug signingConfig's enableV1Signing … enableV4Signing (null: not written, AGP's default). */
    internal fun declaredSigningSchemes(): Map<Int, Boolean?> {
        val inDebugConfig = assigns(moduleScript("app")).filter { (_, outer) -> outer.any { it.name == "signingConfigs" } && outer.any { (it.name == "getByName" || it.name == "named") && literal(it.args.firstOrNull()?.value) == "debug" } }
        return (1..4).associateWith { n -> inDebugConfig.firstOrNull { path(it.first.target) == "enableV${n}Signing" }?.first?.let { value(it.value) }?.toBooleanStrictOrNull() }
    }

    /** gradle/plugin-releases.tsv: plugin id → its versions known to be published. */
    private fun pluginReleases(): Map<String, Set<String>> = file("gradle/plugin-releases.tsv").readLines().map { it.substringBefore('#').trim() }
        .filter { it.isNotEmpty() }.map { it.split(Regex("\\s+")) }.groupBy({ it[0] }, { it[1] }).mapValues { it.value.toSet() }

    private fun releasesExist() {
        val known = pluginReleases()
        val used = ArrayList<Triple<String, String, String>>()
        for (n in script("settings.gradle.kts").filterIsInstance<Call>().filter { it.name == "plugins" }.flatMap { it.lambda!!.body }) {
            if (n is Binary && n.op == "version") used += Triple(idOf(n) ?: "?", literal(n.right) ?: "?", "settings.gradle.kts")
        }
        for (accessor in toml["plugins"].orEmpty().keys) {
            val (id, v) = pluginId(accessor.replace('-', '.'))
            if (v != null) used += Triple(id, v, "gradle/libs.versions.toml")
        }
        for ((id, v, where) in used) {
            val versions = known[id]
            if (versions == null) problem("$where: plugin $id has no row in gradle/plugin-releases.tsv (the versions known to be published)")
            else if (v !in versions) problem("$where: plugin $id $v is not a published version (gradle/plugin-releases.tsv: ${versions.sortedWith(::cmp).joinToString()}): the build fails to resolve it")
        }
        // The Android tools libraries (manifest merger) of the same AGP: 8.x.y ↔ 31.x.y.
        val agp = pluginId("android.application").second ?: return
        val tools = toml["versions"]?.get("android-tools")?.trim('"')
        val expected = "${agp.substringBefore('.').toInt() + 23}.${agp.substringAfter('.')}"
        if (tools != expected) problem("gradle/libs.versions.toml: android-tools is $tools; AGP $agp's tools libraries are $expected")
        if (rootProperties["android.tools.version"] != expected) problem("pom.xml: android.tools.version is ${rootProperties["android.tools.version"]}; AGP $agp's tools libraries are $expected")
        if (rootProperties["agp.version"] != agp) problem("pom.xml: agp.version is ${rootProperties["agp.version"]}, gradle/libs.versions.toml has AGP $agp")
    }

    /** Whether the local Maven repository shows [d] published without a POM (its folder holds no .pom). */
    private fun withoutPom(d: Dep): Boolean {
        val repo = localRepository ?: return false
        val (g, a) = d.coordinates.split(':')
        val dir = File(repo, "${g.replace('.', '/')}/$a/${d.version}")
        return dir.isDirectory && !File(dir, "$a-${d.version}.pom").isFile && dir.list()!!.any { it.startsWith("$a-${d.version}.") }
    }

    private fun metadataSources() {
        val settings = script("settings.gradle.kts")
        val repos = calls(settings).filter { (c, outer) -> c.name == "repositories" && outer.map { it.name } == listOf("dependencyResolutionManagement") }.flatMap { it.first.lambda!!.body }
        val noPom = sharedModules.flatMap { gradleDependencies(it) }.filter(::withoutPom).distinctBy { it.coordinates }
        for (d in noPom) {
            val (g, a) = d.coordinates.split(':')
            val exclusive = repos.filterIsInstance<Call>().firstOrNull { r ->
                r.name == "exclusiveContent" && calls(listOf(r)).any { (c, outer) -> outer.any { it.name == "filter" } && ((c.name == "includeModule" && c.args.mapNotNull { literal(it.value) } == listOf(g, a)) || (c.name == "includeGroup" && literal(c.args.firstOrNull()?.value) == g)) }
            }
            val artifact = exclusive != null && calls(listOf(exclusive)).any { (c, outer) -> c.name == "artifact" && outer.any { it.name == "metadataSources" } && outer.any { it.name == "forRepository" } }
            if (!artifact) problem("settings.gradle.kts: ${d.coordinates}:${d.version} is published without a POM (none beside it in the local Maven repository); Gradle refuses a module without metadata unless its repository declares metadataSources { artifact() } (an exclusiveContent { forRepository { maven { … } } filter { includeModule(\"$g\", \"$a\") } })")
        }
    }

    /** The dependencies a POM in the local repository declares for consumers (compile and runtime scope), versions resolved in that POM. */
    private fun pomDependencies(ga: String, version: String): List<Pair<String, String>> {
        val repo = localRepository ?: return emptyList()
        val (g, a) = ga.split(':')
        val f = File(repo, "${g.replace('.', '/')}/$a/$version/$a-$version.pom")
        if (!f.isFile) return emptyList()
        val pom = BuildFiles.parse(f)
        val props = pom.properties() + mapOf("project.version" to version)
        val managedHere = pom.child("dependencyManagement")?.child("dependencies")?.children("dependency").orEmpty()
            .associate { "${it.text("groupId")}:${it.text("artifactId")}" to it.text("version") }
        return pom.child("dependencies")?.children("dependency").orEmpty()
            .filter { (it.text("scope") ?: "compile") in setOf("compile", "runtime") && it.text("optional") != "true" }
            .mapNotNull { d ->
                val dga = "${d.text("groupId")}:${d.text("artifactId")}"
                val v = d.text("version") ?: managedHere[dga] ?: return@mapNotNull null
                dga to interpolate(v, props)
            }
    }

    private fun gradleConstraints(module: String): List<Pair<String, String>> =
        calls(moduleScript(module)).filter { (_, outer) -> outer.map { it.name } == listOf("dependencies", "constraints") }
            .mapNotNull { (c, _) -> c.args.singleOrNull()?.value?.let { notation(it, null, "$module/build.gradle.kts") } }

    /** Maven's dependencyManagement fixes the version of a library that arrives transitively; Gradle takes the highest asked for unless a constraint says otherwise. */
    private fun managedVersions() {
        val direct = sharedModules.flatMap { m -> mavenDependencies(m).map { m to it } }
        val directCoordinates = direct.map { it.second.coordinates }.toSet()
        val constraints = sharedModules.flatMap { gradleConstraints(it) }
        for ((ga, version) in managed) {
            if (ga in directCoordinates || ga.startsWith("dev.motionfusion:")) continue
            val askers = direct.filter { it.second.configuration != "testImplementation" }.flatMap { (m, d) ->
                pomDependencies(d.coordinates, d.version).filter { it.first == ga && it.second != version }.map { "$m: ${d.coordinates}:${d.version} asks for ${it.second}" }
            }.distinct()
            if (askers.isEmpty()) continue
            val c = constraints.filter { it.first == ga }
            if (c.isEmpty()) problem("Maven's dependencyManagement sets $ga to $version (${askers.joinToString("; ")}); no build.gradle.kts has constraints { implementation(…) } at $version, so Gradle packages another version")
            for ((_, v) in c) if (v != version) problem("a Gradle constraint sets $ga to $v, Maven's dependencyManagement to $version")
        }
    }

    /** Test task inputs Gradle can fingerprint: typed argument providers, never lambdas. */
    private fun cacheableTestInputs() {
        for (module in sharedModules) {
            val where = "$module/build.gradle.kts"
            val nodes = moduleScript(module)
            for ((c, _) in calls(nodes)) if (c.name == "CommandLineArgumentProvider" && c.lambda != null) {
                problem("$where:${c.line}: a lambda CommandLineArgumentProvider: Gradle cannot tell what it reads, so the test task is never taken from the build cache; give a class with @get:InputFile (or @get:InputDirectory) and @get:PathSensitive properties")
            }
            val providers = nodes.filterIsInstance<KotlinDsl.Decl>().filter { it.kind == "class" && "CommandLineArgumentProvider" in it.supertypes }
            for (cls in providers) {
                val props = (cls.value as? KotlinDsl.Lambda)?.body.orEmpty().filterIsInstance<KotlinDsl.Decl>().filter { it.kind == "val" || it.kind == "var" }
                for (p in props) {
                    val input = p.annotations.firstOrNull { it.startsWith("get:Input") || it == "get:Internal" || it == "get:Nested" }
                    if (input == null) problem("$where:${p.line}: ${cls.name}.${p.name} has no @get:Input… annotation: Gradle does not track it")
                    if (input in setOf("get:InputFile", "get:InputFiles", "get:InputDirectory") && "get:PathSensitive" !in p.annotations) {
                        problem("$where:${p.line}: ${cls.name}.${p.name} has no @get:PathSensitive: the absolute path enters the cache key and no other checkout reuses the test results")
                    }
                }
                if (props.none { it.annotations.any { a -> a in setOf("get:InputFile", "get:InputFiles", "get:InputDirectory") } }) problem("$where: ${cls.name} declares no file input")
            }
            val names = providers.map { it.name }.toSet()
            for ((c, _) in calls(nodes)) if (path(c.callee).endsWith("jvmArgumentProviders.add")) {
                var typed = false
                KotlinDsl.walk(c.args.map { it.value }) { n, _ -> if (n is Call && (n.typeArgs.any { it in names } || n.name in names)) typed = true }
                if (!typed) problem("$where:${c.line}: jvmArgumentProviders.add(…) is not given one of the typed providers declared here (${names.ifEmpty { setOf("none") }.joinToString()})")
            }
        }
    }
}
