// fusion-cli: the `fusion` command (fusion-cli/pom.xml; Maven builds target/fusion.jar for bin/fusion).
plugins {
    alias(libs.plugins.kotlin.jvm)
    application
}

kotlin {
    jvmToolchain(17)
    compilerOptions {
        freeCompilerArgs.add("-Xjsr305=strict")
    }
}

sourceSets {
    main { kotlin.srcDirs("src/main/kotlin") }
    test { kotlin.srcDirs("src/test/kotlin") }
}

application {
    mainClass.set("dev.motionfusion.cli.MainKt")
}

dependencies {
    implementation(project(":fusion-core"))
    implementation(project(":fusion-stream"))
    runtimeOnly(libs.slf4j.nop)
    implementation(libs.kotlin.stdlib)
    testImplementation(platform(libs.junit.bom))
    testImplementation(libs.junit.jupiter)
    testRuntimeOnly(libs.junit.platform.launcher)
}

// Maven filters src/main/resources: version.properties gets ${project.version} (`fusion --version`).
tasks.processResources {
    val version = project.version.toString()
    inputs.property("version", version)
    filesMatching("**/version.properties") {
        expand("project" to mapOf("version" to version))
    }
}

tasks.test {
    useJUnitPlatform()
    maxHeapSize = "2g"
}
